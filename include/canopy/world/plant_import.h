#pragma once
// Plants imported from existing models (COLLADA, OBJ, glTF, ... through assimp): geometry
// in metres with +z up and the base at the origin, each material mapped to a semantic class,
// fruit instances as connected components of fruit triangles, and their ground truth. A
// plant is saved as a folder (plant.yaml, meshes/*.obj, fruits.json, fruit_points.csv) that
// world files place by name next to procedural plants. Free of MuJoCo.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "canopy/world/ground_truth.h"
#include "canopy/world/mesh.h"
#include "canopy/world/texture.h"

namespace canopy::world {

/// One rule of the material -> class mapping: materials whose name matches `pattern`
/// (ECMAScript regex, searched anywhere in the name, case-insensitive) get `class_name`.
/// `target` false marks fruit that is labelled and rendered but not scored (unripe).
struct ClassRule {
  std::string class_name;
  std::string pattern;
  bool target = true;
};

/// How ground truth is made from the fruit meshes.
enum class TruthMode {
  kSurface,   ///< Points sampled uniformly by area, about point_spacing_m apart (as procedural worlds).
  kVertices,  ///< The fruit meshes' own (welded) vertices, as published evaluations of these models do.
};

/// What becomes of a material's diffuse texture.
enum class TextureMode {
  kImage,  ///< Rendered with the texture (converted to PNG, texture coordinates in the meshes).
  kMean,   ///< Its mean texel colour (weighted by UV area) becomes the material's flat colour.
};

/// Plausible ranges of the import options (metres per file unit; triangles).
constexpr double kMinUnitScale = 1e-6;
constexpr double kMaxUnitScale = 1e3;
constexpr long kMaxImportTriangles = 10000000;

/// Everything `import_plant` needs besides the file.
struct ImportOptions {
  std::vector<ClassRule> rules;              ///< First match wins.
  std::optional<ClassRule> fallback;         ///< Class of unmatched materials (else they are an error).
  std::string fruit_class = "fruit";         ///< Class whose triangles form fruit instances.
  std::optional<double> unit_scale;          ///< Metres per file unit; overrides the file's own unit.
  std::string up = "auto";                   ///< "z", "y", or "auto" (glTF: y, everything else: z).
  long max_triangles = 200000;               ///< Budget for the whole plant after simplification.
  TruthMode truth = TruthMode::kSurface;
  double point_spacing_m = 0.003;            ///< Ground-truth spacing (procedural worlds' default).
  double weld_tolerance_m = 1e-5;            ///< Vertices closer than this are one vertex.
  double min_fruit_size_m = 0.02;            ///< Fruit components with a smaller bounding-box diagonal are fragments.
  double merge_distance_m = 0.02;            ///< Fragments this close to a fruit join it; farther ones are dropped.
  std::uint64_t seed = 1;                    ///< Seed of the surface sampling.
  TextureMode texture = TextureMode::kImage;
};

/// The rules of a named preset ("capsicum": the community's Gazebo sweet-pepper models,
/// docs/background/capsicum_models.md); throws InputError for an unknown name.
std::vector<ClassRule> class_preset(const std::string& name);
/// Parses a command-line mapping "CLASS=REGEX" or "CLASS:unripe=REGEX"; throws InputError.
ClassRule parse_class_rule(const std::string& text);

/// One material group of the imported plant: a mesh with one class and colour. Fruit
/// instances are groups of their own (fruit >= 0).
struct ImportedPart {
  std::string material;
  std::string class_name;
  bool target = true;            ///< Fruits only: counts in the coverage metric.
  int fruit = -1;                ///< Index of the fruit instance in the plant, -1 for other parts.
  float rgba[4] = {0.5f, 0.5f, 0.5f, 1.f};  ///< Flat colour (white under a texture).
  TriMesh mesh;                  ///< Plant frame: metres, +z up, base at the origin.
  /// Textured parts: the texture (shared by the parts of one material), its file in the
  /// plant folder ("textures/NAME.png") and the texture coordinates of every face.
  std::shared_ptr<const Image<Rgb8>> texture;
  std::string texture_file;
  std::vector<FaceUv> uv;
};

/// What the import did with one material's colour.
struct MaterialReport {
  std::string name;
  std::string class_name;
  bool target = true;
  long triangles = 0;
  /// Its diffuse texture as the file names it ("VG07frt1.tga"; "*0" for the first texture
  /// embedded in the file, as in glTF);
  /// "" when it has none.
  std::string texture_source;
  int texture_width = 0, texture_height = 0;
  /// "image" (rendered with it), "mean" (its mean colour baked in), "flat" (no texture:
  /// the file's diffuse colour or the class colour), "missing" (the texture file was not
  /// found: flat colour), "no-uv" (no texture coordinates: the texture's plain mean).
  std::string colour = "flat";
  float rgba[4] = {0.5f, 0.5f, 0.5f, 1.f};  ///< Flat colour rendered; under a texture, its mean.
  /// What colour segmentation labels its colours ("fruit 0.97, background 0.03"), and the
  /// problem with that ("" for none): filled by the import command's check.
  std::string color_segmentation, color_problem;
};

/// What the import found, for the report and plant.yaml.
struct ImportReport {
  std::string format;            ///< assimp's name of the file format, when it says.
  double file_unit_m = 1.0;      ///< The file's own unit [m per unit] (COLLADA <unit>, else 1).
  double unit_scale = 1.0;       ///< The scale applied [m per unit].
  std::string up;                ///< Up axis used ("z" or "y").
  Vec3 size_m = Vec3::Zero();    ///< Bounding-box size in the plant frame.
  double radius_m = 0.0;         ///< Largest horizontal distance of any vertex from the base.
  long triangles_in = 0;         ///< Triangles in the file, counted per node instance.
  long degenerate_dropped = 0;   ///< Zero-area triangles dropped (after welding).
  long non_triangles_dropped = 0;  ///< Points and lines dropped.
  long duplicate_triangles = 0;  ///< Triangles that exactly repeat another one (kept, counted once in the ground truth).
  std::vector<std::string> duplicate_nodes;  ///< Node pairs "A = B" whose instances coincide.
  double simplify_cell_m = 0.0;  ///< Vertex-clustering cell used to meet the budget (0: none).
  long fragments_merged = 0;     ///< Small fruit components merged into their nearest fruit.
  long fragments_dropped = 0;    ///< Small fruit components dropped (no fruit nearby).
  std::vector<std::string> warnings;
  std::vector<MaterialReport> materials;  ///< Materials with triangles, in the file's order.
};

/// An imported plant: parts, fruit ground truth (plant frame, plant_index 0) and the report.
struct ImportedPlant {
  std::string source_path;
  std::string source_sha256;
  ImportOptions options;
  std::vector<ImportedPart> parts;
  GroundTruth truth;
  ImportReport report;

  long triangle_count() const;
  /// Writes the plant folder's files into `dir` (which must exist): plant.yaml,
  /// meshes/<part>.obj, fruits.json, fruit_points.csv, each atomically.
  void save(const std::string& dir) const;
};

/// Reads `path` with assimp and builds the plant. Throws InputError (one line, naming the
/// file) on a missing or unreadable file, no mesh, unmatched materials, no fruit material,
/// a bad regex, a scale <= 0 or a triangle budget that cannot be met.
ImportedPlant import_plant(const std::string& path, const ImportOptions& options);

/// A saved plant folder read back: what a world needs to place it.
struct PlantAsset {
  std::string dir;
  double height_m = 0.0;
  double radius_m = 0.0;
  std::vector<ImportedPart> parts;  ///< Plant frame.
  GroundTruth truth;                ///< Plant frame; fruits indexed by ImportedPart::fruit.
};

/// Reads only the size entries of `<dir>/plant.yaml` (for world validation).
void read_plant_size(const std::string& dir, double* height_m, double* radius_m);
/// Reads a plant folder written by ImportedPlant::save; throws InputError naming the file.
PlantAsset load_plant_asset(const std::string& dir);

/// Reads a mesh file (any format assimp reads, e.g. a part's OBJ) into one mesh, node
/// transforms applied, coincident vertices merged. `uv`, when given, receives every face's
/// texture coordinates (channel 0; InputError when the file has none).
TriMesh read_mesh_file(const std::string& path, std::vector<FaceUv>* uv = nullptr);

/// Hex SHA-256 of a file's bytes (InputError when it cannot be read).
std::string file_sha256(const std::string& path);

}  // namespace canopy::world
