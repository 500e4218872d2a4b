#pragma once
// How hidden the ripe fruits of a world are to a camera, measured as Hemming et al. (2014,
// Sensors 14(4):6032) measured a commercial sweet-pepper crop: fixed camera positions per
// plant section of a row, at several azimuth and zenith angles, and a fruit counted detectable
// from a position when at most half of its camera-facing surface is hidden by other objects.
// The protocol and the positions are written out in docs/visibility.md.
//
// Geometry only: ray casts from each camera to the fruits' ground-truth surface points against
// the world's triangle meshes (every plant part, and the greenhouse fixtures of the world).
// Reads the ground truth, so it lives in evaluation (never in mapping, nbv or motion).

#include <array>
#include <string>
#include <vector>

#include "canopy/common/camera.h"
#include "canopy/common/types.h"
#include "canopy/world/world.h"

namespace canopy::evaluation {

/// One camera position of the protocol, relative to a plant section: the view direction's
/// azimuth (rotation about the vertical, 0 = square to the row, positive towards +x along the
/// row) and zenith angle (from straight up: 90 = level, 60 = looking up 30 degrees above the
/// horizon, 120 = looking down 30 degrees).
struct CameraPosition {
  std::string name;
  double azimuth_deg = 0.0;
  double zenith_deg = 90.0;
};

/// The 14 positions per plant section (docs/visibility.md says which are the study's and how
/// canopy reads them).
std::vector<CameraPosition> hemming_positions();

/// What the protocol needs beside the world.
struct VisibilityParams {
  std::vector<CameraPosition> positions = hemming_positions();
  double distance_m = 0.5;         ///< Camera to the section's centre, along the view direction.
  double section_width_m = 0.4;    ///< Plant sections tile each row: width along the row ...
  double section_height_m = 0.4;   ///< ... and height (both fit the default camera's image at 0.5 m).
  double max_occlusion = 0.5;      ///< Detectable: at most this share of the facing surface hidden.
  int points_per_fruit = 300;      ///< Ground-truth surface points used per fruit (evenly subsampled).
  CameraIntrinsics camera;         ///< "In the image": the fruit's centre projects inside it.
  bool include_unripe = false;     ///< Also measure unripe (green) fruits (they still occlude).
};

/// Triangles of a world with, per triangle, the part it belongs to; answers the first hit of
/// a ray through a bounding-volume hierarchy over all triangles (imported plants bring parts
/// of 100,000 triangles), or, for one part, that part's triangles.
class RayScene {
 public:
  explicit RayScene(const world::World& world);
  /// A scene of explicit meshes (tests): part i is meshes[i].
  explicit RayScene(const std::vector<world::TriMesh>& meshes);

  /// Nearest hit of origin + t * dir (dir unit) for t in (0, max_t): the part index, or -1.
  /// `only_part` >= 0 tests that part alone.
  int first_hit(const Vec3& origin, const Vec3& dir, double max_t, double* t_hit, int only_part = -1) const;
  /// The part index of fruit instance `instance_id` (-1 when none).
  int part_of_instance(int instance_id) const;
  size_t part_count() const { return parts_.size(); }

 private:
  struct Part {
    Vec3 lo, hi;
    size_t first = 0, count = 0;  ///< Triangles [first, first + count) of tris_.
    int instance_id = -1;
  };
  struct Node {
    Vec3 lo, hi;
    int left = -1, right = -1;    ///< Children (-1: a leaf).
    size_t first = 0, count = 0;  ///< Leaf: entries [first, first + count) of order_.
  };
  void add_part(const world::TriMesh& mesh, int instance_id);
  void build();
  int build_node(size_t begin, size_t end, const std::vector<Vec3>& centroids);
  std::vector<Part> parts_;
  std::vector<std::array<Vec3, 3>> tris_;
  std::vector<int> part_of_tri_;
  std::vector<size_t> order_;     ///< Triangle indices in the hierarchy's leaf order.
  std::vector<Node> nodes_;
};

/// One fruit seen from one camera.
struct FruitView {
  int facing_points = 0;   ///< Surface points facing the camera (their ray meets the fruit there first).
  int hidden_points = 0;   ///< ... of which another object hides.
  bool in_image = false;   ///< The fruit's centre projects inside the image.
  double occlusion() const { return facing_points > 0 ? double(hidden_points) / facing_points : 1.0; }
};

/// Looks at `points` (on the surface of scene part `fruit_part`) from `eye`. A point faces the
/// camera when the ray from the eye meets its own fruit first within `tolerance_m` of the
/// point; a facing point is hidden when another part meets the ray before it.
FruitView view_fruit(const RayScene& scene, int fruit_part, const std::vector<Vec3>& points, const Vec3& eye,
                     double tolerance_m = 0.004);

/// A camera of the protocol: a position of one section.
struct SectionCamera {
  int section = 0;
  int position = 0;
  Vec3 eye = Vec3::Zero();
  Vec3 target = Vec3::Zero();
  Pose pose = Pose::Identity();  ///< Optical frame (look_at).
};

/// A plant section: a tile of a row's plane, seen from the aisle.
struct Section {
  int row = 0;                 ///< 0: the row at y > 0, 1: at y < 0.
  Vec3 center = Vec3::Zero();  ///< On the row's centre line.
  Vec3 toward_aisle = Vec3::Zero();
};

/// One measured fruit: its section and its view from each position.
struct FruitVisibility {
  int instance_id = 0;
  int plant_index = 0;
  int section = 0;
  std::vector<FruitView> views;  ///< Per position.
  std::vector<bool> detectable;  ///< Per position: in the image and at most max_occlusion hidden.
};

/// Fruit detectability of the best combination of k positions.
struct BestCombination {
  int k = 0;
  std::vector<int> positions;
  double detectability = 0.0;  ///< Share of measured fruits detectable from at least one of them.
};

struct VisibilityResult {
  VisibilityParams params;
  std::vector<Section> sections;
  std::vector<SectionCamera> cameras;
  std::vector<FruitVisibility> fruits;
  std::vector<double> detectability;   ///< Per position.
  std::vector<double> mean_occlusion;  ///< Per position, over measured fruits.
  std::vector<BestCombination> best;   ///< k = 1 .. min(5, positions), exhaustive search.
};

/// Camera eye for a section centre `target`, the unit direction from the row to the aisle
/// `toward_aisle` (horizontal), the row direction `along_row` and a position.
Vec3 camera_eye(const Vec3& target, const Vec3& toward_aisle, const Vec3& along_row, const CameraPosition& position,
                double distance_m);

/// Runs the protocol on a world: sections over each row's (ripe) fruits, every position's
/// camera per section, and each fruit seen from its own section's cameras. Deterministic.
VisibilityResult measure_visibility(const world::World& world, const VisibilityParams& params = {});

/// The best combination of k positions (exhaustive over all combinations; ties: the first in
/// lexicographic order), from per-fruit detectability.
BestCombination best_combination(const std::vector<FruitVisibility>& fruits, int positions, int k);

}  // namespace canopy::evaluation
