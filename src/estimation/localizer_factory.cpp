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

LocalizerSettings log_settings() { return LocalizerSettings{}; }

LocalizerSettings exact_map_settings() {
  LocalizerSettings s;
  s.vdt_opt = VdtOptimizerOptions{};
  s.vdt_ekf = VdtEkfOptions{};
  s.udt = UdtOptions{};
  s.active_ekf = ActiveBeamLocalizerOptions{};
  s.passive_ekf = LocalizerSettings::passive_beam();
  return s;
}

LocalizerSettings cloud_settings() {
  LocalizerSettings s;
  s.vdt_opt = vdt_opt_defaults(3);
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
