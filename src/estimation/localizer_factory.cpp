#include "vdtnav/estimation/localizer_factory.hpp"

#include <algorithm>

#include "vdtnav/core/error.hpp"
#include "vdtnav/map/surface_roughness.hpp"

namespace vdtnav {

const std::vector<std::string>& localizer_methods() {
  static const std::vector<std::string> kMethods{"vdt-opt", "vdt-ekf",    "udt-opt",    "udt-ekf",
                                                 "pf",      "active-ekf", "passive-ekf"};
  return kMethods;
}

LocalizerSettings log_settings() {
  LocalizerSettings s;
  s.vdt_ekf.motion = MotionModelKind::kOdometryIncrement;
  s.udt.motion = MotionModelKind::kOdometryIncrement;
  s.active_ekf.ekf.motion = MotionModelKind::kOdometryIncrement;
  s.passive_ekf.ekf.motion = MotionModelKind::kOdometryIncrement;
  s.vdt_opt.loss = RobustLoss::kCauchy;
  s.vdt_opt.loss_scale = 0.05;
  s.vdt_opt.search.search_below = 0.95;
  s.vdt_opt.max_iterations = 50;
  // A map drawn from scans: its errors are shared along its walls (vdt_sensor_model.hpp).
  for (VdtSensorModelOptions* o : {&s.vdt_opt.sensor, &s.vdt_ekf.sensor}) {
    o->map_correlation_length = 2.0;
    o->map_pose_sigma = -1.0;
  }
  return s;
}

namespace {

/// The optimizer for maps drawn from real scans or clouds (cloud_settings()).
VdtOptimizerOptions cloud_optimizer() {
  VdtOptimizerOptions o;
  o.loss = RobustLoss::kCauchy;  // what one scan's map lacks or misplaces: cars, vegetation
  o.loss_scale = 0.05;
  o.max_iterations = 50;  // the Cauchy IRLS passes need more than the 25 of an exact map
  o.variance_factor = true;
  o.sensor.map_correlation_length = 1.0;
  o.sensor.map_pose_sigma = -1.0;
  return o;
}

}  // namespace

VdtLocalizer3Options LocalizerSettings::localize3d_defaults() {
  VdtLocalizer3Options o;
  // What `vdtnav localize3d` built before the settings file had a localize3d section: the
  // optimizer is cloud_settings()'s (so not VdtLocalizer3Options's coarse_threshold and
  // function_tolerance), --min-explained 0.3, explained at 0.1 m (the multi-start's distance).
  o.optimizer = cloud_optimizer();
  o.accept_fraction = 0.3;
  o.explained_distance = o.multi_start.explained_distance;
  o.multi_start.enabled = false;    // --multi-start
  o.multi_start.attitude_grid = 2;  // from an identity guess 10-15 degrees off (the car pair)
  // Lost at LostDetectionOptions's levels: the contradiction counts the beams that pass through
  // the map's surfaces (scan_agreement.hpp), not every reading the map does not explain.
  return o;
}

LocalizerSettings cloud_settings() {
  LocalizerSettings s;
  s.vdt_opt = cloud_optimizer();
  return s;
}

std::unique_ptr<Localizer2D> make_localizer(const std::string& method, const VdtMap2& vdt,
                                            const OccupancyGrid<2>& occupancy,
                                            const LocalizerSettings& settings,
                                            const MapKnowledge& knowledge) {
  if (method == "vdt-opt" || method == "vdt-ekf") {
    std::unique_ptr<Localizer2D> tracker;
    if (method == "vdt-opt") {
      tracker = std::make_unique<VdtOptimizationLocalizer>(vdt, settings.vdt_opt);
    } else {
      tracker = std::make_unique<VdtEkfLocalizer>(vdt, settings.vdt_ekf);
    }
    if (!settings.recovery.detect) return tracker;
    GlobalLocalizationOptions global = settings.global;
    global.optimizer = settings.vdt_opt;
    return std::make_unique<RecoveringLocalizer>(std::move(tracker), vdt, occupancy, global,
                                                 settings.recovery, knowledge);
  }
  if (method == "udt-opt")
    return std::make_unique<UdtOptimizationLocalizer>(occupancy, settings.udt);
  if (method == "udt-ekf") return std::make_unique<UdtEkfLocalizer>(occupancy, settings.udt);
  if (method == "pf") return std::make_unique<ParticleFilterLocalizer>(occupancy, settings.pf);
  if (method == "active-ekf" || method == "passive-ekf") {
    ActiveBeamLocalizerOptions o =
        method == "active-ekf" ? settings.active_ekf : settings.passive_ekf;
    // One reading per update leans on the map at each endpoint: the per-reading floor is the
    // map's measured wall roughness unless set (map/surface_roughness.hpp).
    if (o.ekf.sensor.map_sigma < 0.0) {
      o.ekf.sensor.map_sigma = measure_surface_roughness(occupancy).floor;
    }
    return std::make_unique<ActiveBeamLocalizer>(vdt, o, method);
  }
  std::string known;
  for (const auto& m : localizer_methods()) known += (known.empty() ? "" : ", ") + m;
  throw ConfigError("unknown localization method '" + method + "' (expected one of: " + known +
                    ")");
}

}  // namespace vdtnav
