// plan_from_frames FRAMES_DIR X,Y,YAW: maps a recorded RGB-D sequence (canopy frame folders
// or a TUM RGB-D folder with camera.yaml) and prints the next views the arm should take
// from the base at (x, y, yaw), in tour order from its home configuration.
// The robot model comes from canopy's data folder (CANOPY_DATA_DIR, or <prefix>/share/canopy
// beside an installed executable).

#include <cstdio>
#include <exception>

#include "canopy/common/error.h"
#include "canopy/common/value_text.h"
#include "canopy/datasets/frame_sequence.h"
#include "canopy/datasets/sequence_mapping.h"
#include "canopy/mapping/map_params.h"
#include "canopy/motion/view_reach.h"

int main(int argc, char** argv) {
  using namespace canopy;
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s FRAMES_DIR X,Y,YAW\n", argv[0]);
    return 2;
  }
  try {
    const BasePose base = parse_base_pose(argv[2], "base pose");
    const RobotConfig robot = default_robot_config();
    const motion::RobotModel model = motion::RobotModel::load(robot);

    // The map: the struct defaults are the paper's settings (configs/mapping.yaml).
    const mapping::SemanticMapParams map_params;
    const perception::ExtractorParams extractor_params;
    const datasets::FrameSequence frames = datasets::FrameSequence::open(argv[1]);
    mapping::SemanticOcTree map(map_params, frames.classes());
    mapping::ScanInserter inserter(map);
    perception::SemanticExtractor extractor(extractor_params, frames.classes());
    const datasets::SequenceMapResult mapped = datasets::map_sequence(frames, extractor, inserter);
    std::printf("mapped %zu frames (%zu skipped) from %s: %zu occupied voxels\n", mapped.mapped, mapped.skipped.size(),
                argv[1], map.counts().occupied);

    // The next views: the paper's planner with the OSAMCEP gain, for fruit within 1 m of the arm.
    nbv::ViewPlannerSettings settings;
    const std::unique_ptr<nbv::ViewPlanner> planner = nbv::make_view_planner(settings);
    motion::NextViewsRequest request;
    request.base = base;
    request.q = robot.home;
    const Vec3 arm = motion::RobotModel::T_world_base(base) * model.T_base_arm().translation();
    request.region = Eigen::AlignedBox3d(arm - Vec3(1.0, 1.0, arm.z()), arm + Vec3(1.0, 1.0, 2.0));
    const motion::NextViews next =
        motion::plan_next_views(map, *planner, model, motion::MotionConfig::defaults(robot), request);
    std::printf("%zu clusters, %zu next views (%zu without IK)%s%s\n", next.batch.clusters, next.ordered.size(),
                next.unreachable.size(), next.batch.reason.empty() ? "" : ": ", next.batch.reason.c_str());
    for (std::size_t i = 0; i < next.ordered.size(); ++i) {
      const nbv::PlannedView& v = next.ordered[i];
      const Vec3 p = v.T_world_camera.translation();
      std::printf("view %zu: camera (%.3f, %.3f, %.3f), cluster %d, gain %.3g, joints", i + 1, p.x(), p.y(), p.z(),
                  v.cluster, v.gain);
      for (double q : v.q) std::printf(" %.3f", q);
      std::printf("\n");
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "plan_from_frames: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "plan_from_frames: %s\n", e.what());
    return 1;
  }
  return 0;
}
