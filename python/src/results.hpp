#pragma once
// The settings and results the 2D and 3D bindings share.
#include <pybind11/pybind11.h>

#include "vdtnav/estimation/localizer_factory.hpp"

namespace vdtnav::python {

namespace py = pybind11;

/// \brief Settings from what Python passes: None (`defaults`), a vdtnav.Settings, a dict (its
/// keys over `defaults`, as a settings file's) or a path to a YAML settings file (over `defaults`).
[[nodiscard]] LocalizerSettings settings_from(const py::object& settings,
                                              const LocalizerSettings& defaults);

/// \brief Checks a scan's explicit angles against its ranges (one each).
/// \throws ValueError naming `what`.
void check_scan(const LaserScan& scan, const char* what);

/// \brief A status as Python sees it: to_string() with '_' for ' ' ("too_few_observations").
[[nodiscard]] std::string status_token(LocalizationStatus s);

/// \brief LocalizationResult (2D) and LocalizationResult3.
void bind_results(py::module_& m);

}  // namespace vdtnav::python
