#pragma once
/// \file
/// \brief Every 2D localizer by its table name ("vdt-opt", "vdt-ekf", "udt-opt", "udt-ekf",
/// "pf"), so that command-line tools and studies run them side by side on the same data.

#include <memory>
#include <string>
#include <vector>

#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/particle_filter.hpp"
#include "vdtnav/estimation/udt_localizers.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"

namespace vdtnav {

/// \brief The options of each method; a factory call uses the one its method needs.
struct LocalizerSettings {
  VdtOptimizerOptions vdt_opt;
  VdtEkfOptions vdt_ekf;
  UdtOptions udt;
  ParticleFilterOptions pf;
};

/// \return the method names make_localizer() knows, in table order.
[[nodiscard]] const std::vector<std::string>& localizer_methods();

/// \brief A localizer by name. The VDT methods use `vdt`, the UDT methods and the particle filter
/// the occupancy grid it was built from; both must outlive the localizer.
/// \throws ConfigError for an unknown method (the message lists the known ones).
[[nodiscard]] std::unique_ptr<Localizer2D> make_localizer(const std::string& method,
                                                          const VdtMap2& vdt,
                                                          const OccupancyGrid<2>& occupancy,
                                                          const LocalizerSettings& settings = {});

}  // namespace vdtnav
