#pragma once
/// \file
/// \brief Every localizer setting in one documented YAML file (`vdtnav localize --config`,
/// `vdtnav localize3d --config`, `--print-config`), the way nav2's AMCL parameter files work.
///
/// The file is a mapping from a section to its keys:
///
///     sensor: {gate: 0.5} # VdtSensorModelOptions shared by every 2D VDT method (below)
///     vdt-opt:            # VdtOptimizerOptions
///       loss: cauchy
///       sensor: {gate: 0.4}   # overrides the shared block's gate for vdt-opt
///       search: {explained_distance: 0.1, odometry_noise: {a_tt: 0.05}}
///     vdt-ekf: {...}      # VdtEkfOptions (its `start` section: a vdt-opt section)
///     udt: {...}          # UdtOptions, shared by udt-opt and udt-ekf
///     pf: {...}           # ParticleFilterOptions
///     localize3d: {...}   # VdtLocalizer3Options (vdtnav localize3d)
///
/// The shared `sensor:` block (the sensor model and the map-error model, map_sigma,
/// map_correlation_length, map_pose_sigma) reaches the sensor model of vdt-opt, vdt-ekf (and its
/// start) and the EKF of active-ekf and passive-ekf (and their starts), not the 3D localizer's
/// (a 3D map). It is read first, wherever it stands; a method's own `sensor:` keys override it
/// key by key, and a file without it reads as before it existed.
///
/// Every key is optional: a missing key keeps the default it is read over. An unknown key, a
/// value of the wrong type or a non-finite number (but `.nan` for localize3d's
/// held_attitude_sigma, "not estimated") is an error naming the file, the line and the key's path
/// (a typo never silently keeps a default). localizer_settings_yaml() writes every key with its
/// unit and meaning as a comment: the reference docs/settings.md holds.

#include <string>

#include "vdtnav/estimation/localizer_factory.hpp"

namespace vdtnav {

/// \brief The section a method reads: its own name, but "udt-opt" and "udt-ekf" read "udt";
/// "localize3d" (the 3D command) reads "localize3d".
[[nodiscard]] std::string localizer_config_section(const std::string& method);

/// \brief Reads settings from YAML text over `defaults`; `source` names the text in errors.
/// \throws ConfigError for malformed YAML, an unknown section or key, a value of the wrong type
/// (message: "<source>:<line>: <path>: ...").
[[nodiscard]] LocalizerSettings parse_localizer_config(const std::string& text,
                                                       const std::string& source,
                                                       const LocalizerSettings& defaults);

/// \brief Reads a settings file over `defaults`. \throws ConfigError as parse_localizer_config,
/// or when the file cannot be read.
[[nodiscard]] LocalizerSettings load_localizer_config(const std::string& path,
                                                      const LocalizerSettings& defaults);

/// \brief The settings as a documented YAML file (every key, its unit and meaning in a comment),
/// all sections, or only the one `method` reads (e.g. "vdt-opt") with the shared sensor block,
/// global and recovery ("localize3d": its section alone). The shared block holds vdt-opt's sensor
/// model, each method's `sensor:` only the keys that differ from it. Reading it back gives the
/// same settings (for one method: that method's).
/// \throws ConfigError for an unknown method.
[[nodiscard]] std::string localizer_settings_yaml(const LocalizerSettings& settings,
                                                  const std::string& method = "");

}  // namespace vdtnav
