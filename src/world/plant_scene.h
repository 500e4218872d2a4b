#pragma once
// Internal to the plant import: a model file read with assimp (triangulated, identical
// vertices joined, its COLLADA Z-up -> Y-up rotation switched off), its node tree walked into
// one triangle soup per material (every node instance with its own transform), its unit,
// format and textures. plant_import.cpp turns the soups into a plant; only this unit
// includes assimp.

#include <Eigen/Core>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "canopy/common/image.h"
#include "canopy/common/types.h"
#include "canopy/world/plant_import.h"

struct aiScene;
namespace Assimp {
class Importer;
}

namespace canopy::world {

/// One material's triangles in the plant frame, with an "exact duplicate" flag per triangle.
struct MaterialSoup {
  std::string name;
  std::vector<std::array<Vec3, 3>> triangles;
  std::vector<bool> duplicate;
  std::vector<FaceUv> uv;    ///< per triangle; NaN where its mesh has no texture coordinates
  long without_uv = 0;       ///< triangles without texture coordinates
  std::string texture_ref;   ///< its diffuse texture as the material names it ("" for none)
  bool has_texture = false;
  bool has_color = false;
  float rgba[4] = {0.5f, 0.5f, 0.5f, 1.f};
};

/// A model file as assimp reads it; owns the scene.
class PlantScene {
 public:
  /// Reads `path`; throws InputError when it is not a file, assimp cannot read it or it
  /// holds no mesh.
  explicit PlantScene(const std::string& path);
  ~PlantScene();
  PlantScene(const PlantScene&) = delete;
  PlantScene& operator=(const PlantScene&) = delete;

  /// assimp's name of the file format ("" when it does not say).
  std::string format() const;
  /// The file's own unit [m per unit]: COLLADA's <unit meter>, else 1.
  double file_unit_m() const;
  /// The up axis the file's format implies: "y" for glTF, "z" for everything else.
  std::string default_up() const;
  /// Every node instance's triangles, transformed by `T_out_file * (node chain)`, into one
  /// soup per material, with the materials' diffuse colours and textures. Counts in `report`
  /// what is dropped (points, lines), what comes in and what repeats exactly.
  std::vector<MaterialSoup> triangles_by_material(const Eigen::Matrix4d& T_out_file, ImportReport* report) const;
  /// The diffuse texture `ref` of a material, decoded: embedded in the file (glTF, "*0") or
  /// an image file beside it (as named, relative to the model's folder, or its bare file
  /// name there). nullopt when no such file exists; InputError when it is not an image.
  std::optional<Image<Rgb8>> load_texture(const std::string& ref) const;

 private:
  std::string path_;
  std::unique_ptr<Assimp::Importer> importer_;
  const aiScene* scene_ = nullptr;  ///< owned by importer_
};

}  // namespace canopy::world
