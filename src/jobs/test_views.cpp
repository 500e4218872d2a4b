#include "canopy/jobs/test_views.h"

#include "canopy/sim/renderer.h"

namespace canopy::jobs {

evaluation::RingViews default_test_ring() {
  evaluation::RingViews ring;
  ring.azimuths = 8;
  ring.radius_m = 0.45;
  ring.heights = {0.3, 0.575, 0.85};
  return ring;
}

void render_test_views(datasets::DatasetExport& dataset, sim::Simulator& sim, const world::World& world,
                       const evaluation::RingViews& ring) {
  CameraIntrinsics K = dataset.intrinsics();
  K.depth_noise_k = 0.0;
  sim::Renderer renderer(sim, K);
  for (const Pose& T : evaluation::ring_views(world, ring)) dataset.add_test(renderer.render_free_camera(T));
}

}  // namespace canopy::jobs
