#pragma once
/// \file
/// \brief Every 2D localizer setting in one documented YAML file (`vdtnav localize --config`,
/// `--print-config`), the way nav2's AMCL parameter files work.
///
/// The file is a mapping from a method's section to its keys:
///
///     vdt-opt:            # VdtOptimizerOptions
///       loss: cauchy
///       sensor: {gate: 0.5}
///       search: {explained_distance: 0.1, odometry_noise: {a_tt: 0.05}}
///     vdt-ekf: {...}      # VdtEkfOptions (its `start` section: a vdt-opt section)
///     udt: {...}          # UdtOptions, shared by udt-opt and udt-ekf
///     pf: {...}           # ParticleFilterOptions
///
/// Every key is optional: a missing key keeps the default it is read over. An unknown key, a
/// value of the wrong type or a non-finite number is an error naming the file, the line and the
/// key's path (a typo never silently keeps a default). localizer_settings_yaml() writes every
/// key with its unit and meaning as a comment: the reference the README's table is made from.

#include <string>

#include "vdtnav/estimation/localizer_factory.hpp"

namespace vdtnav {

/// \brief The section names of a settings file, in file order ("vdt-opt", "vdt-ekf", "udt",
/// "pf"), and the section a method reads ("udt-opt" and "udt-ekf" read "udt").
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
/// all sections, or only the one `method` reads (e.g. "vdt-opt"). Reading it back gives the same
/// settings.
/// \throws ConfigError for an unknown method.
[[nodiscard]] std::string localizer_settings_yaml(const LocalizerSettings& settings,
                                                  const std::string& method = "");

}  // namespace vdtnav
