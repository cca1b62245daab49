// The localizers' defaults for maps drawn from real scans and clouds (vdt_opt_defaults(),
// vdt_ekf_defaults(), udt_defaults(), vdt_localizer3_defaults()): what the constructors,
// LocalizerSettings{}, the CLI, the Python module and the ROS node run without a settings file.
// The options structs' own values are the thesis's exact-map solver (exact_map_settings()).
#include "vdtnav/estimation/udt_localizers.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/estimation/vdt_localizer3d.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"

#include "vdtnav/core/error.hpp"

namespace vdtnav {

VdtOptimizerOptions vdt_opt_defaults(int dimension) {
  VDTNAV_CHECK(dimension == 2 || dimension == 3, "vdt_opt_defaults: dimension must be 2 or 3");
  VdtOptimizerOptions o;
  o.loss = RobustLoss::kCauchy;  // what the map lacks or misplaces: furniture, people, cars
  o.loss_scale = 0.05;
  o.max_iterations = 50;  // the Cauchy IRLS passes need more than the 25 of an exact map
  // A map drawn from scans: its errors are shared along its surfaces (vdt_sensor_model.hpp),
  // per 2 m square of walls in 2D, per 1 m cube in 3D; the builder's pose error half a cell.
  o.sensor.map_correlation_length = dimension == 2 ? 2.0 : 1.0;
  o.sensor.map_pose_sigma = -1.0;
  if (dimension == 2) {
    o.search.search_below = 0.95;  // the window search on every scan explained below 95 %
  } else {
    o.variance_factor = true;  // the residuals say when the cloud map is rougher than its floor
  }
  return o;
}

VdtEkfOptions vdt_ekf_defaults() {
  VdtEkfOptions o;
  o.motion = MotionModelKind::kOdometryIncrement;
  o.sensor.map_correlation_length = vdt_opt_defaults(2).sensor.map_correlation_length;
  o.sensor.map_pose_sigma = -1.0;
  return o;
}

UdtOptions udt_defaults() {
  UdtOptions o;
  o.motion = MotionModelKind::kOdometryIncrement;
  return o;
}

VdtLocalizer3Options vdt_localizer3_defaults() {
  VdtLocalizer3Options o;
  // The optimizer of the clouds (so not VdtLocalizer3Options's coarse_threshold and
  // function_tolerance), --min-explained 0.3, explained at 0.1 m (the multi-start's distance).
  o.optimizer = vdt_opt_defaults(3);
  o.accept_fraction = 0.3;
  o.explained_distance = o.multi_start.explained_distance;
  o.multi_start.enabled = false;    // --multi-start
  o.multi_start.attitude_grid = 2;  // from an identity guess 10-15 degrees off (the car pair)
  // Lost at LostDetectionOptions's levels: the contradiction counts the beams that pass through
  // the map's surfaces (scan_agreement.hpp), not every reading the map does not explain.
  return o;
}

}  // namespace vdtnav
