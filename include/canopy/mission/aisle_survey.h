#pragma once
// The foundation's main job: drive the robot along the aisle, stop beside each pair of
// plants, point the wrist camera at the left and the right row and render what it sees.
// The full active-mapping mission builds on the same loop (drive, move arm, observe).

#include <functional>
#include <string>
#include <vector>

#include "canopy/common/frame.h"
#include "canopy/sim/renderer.h"
#include "canopy/sim/simulator.h"

namespace canopy::mission {

/// Settings of the survey.
struct SurveyParams {
  double arm_settle_tolerance_rad = 1e-3;  ///< Arm counts as settled within this.
  double arm_timeout_s = 6.0;              ///< Give up settling after this long.
  double base_timeout_s = 30.0;            ///< Give up driving to a stop after this long.
  double stop_offset_m = -0.2;             ///< Base x relative to a plant pair (arm base is +0.2 m ahead).
};

/// What happened at one observation.
struct SurveyObservation {
  int stop = 0;
  std::string side;            ///< "left" (+y row) or "right" (-y row).
  BasePose base;               ///< Base pose reached.
  double arm_error_rad = 0.0;  ///< Max joint error when the frame was taken.
  double settle_time_s = 0.0;
  LabelledFrame frame;
};

/// Outcome of a survey.
struct SurveyResult {
  std::vector<SurveyObservation> observations;
  std::vector<BasePose> stop_goals;
  std::vector<double> stop_position_error_m;
  double sim_time_s = 0.0;
  bool all_stops_reached = true;
};

/// Callbacks: progress messages (the library does not print) and a video tick, called with
/// the simulated time every `video_period_s` of simulated time (0: never).
struct SurveyCallbacks {
  std::function<void(const std::string& message)> progress;
  std::function<void(double sim_time_s)> video_tick;
  double video_period_s = 0.0;
};

/// Drives the aisle of `spec`'s world in `sim`, rendering with `renderer`.
SurveyResult run_aisle_survey(sim::Simulator& sim, sim::Renderer& renderer, const world::WorldSpec& spec,
                              const SurveyParams& params, const SurveyCallbacks& callbacks = {});

}  // namespace canopy::mission
