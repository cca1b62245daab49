#pragma once
// The sections of the settings file (private to the estimation component): their names in file
// order, what each holds, and the sensor models the shared sensor: block reaches.

#include <string>
#include <vector>

#include "localizer_config_keys.hpp"
#include "localizer_config_keys3d.hpp"

namespace vdtnav::config_keys {

/// The shared block: the VDT sensor model of every 2D VDT method, read before the methods'
/// sections (whose own sensor: keys override it key by key).
inline const char* const kSharedSensor = "sensor";
/// The 3D localizer's section (`vdtnav localize3d`).
inline const char* const kLocalize3d = "localize3d";
/// The one top-level key that is not a section: the pool's thread count (core/parallel.hpp).
inline const char* const kThreads = "threads";
inline const char* const kThreadsDoc =
    "[threads] threads of the work that runs in parallel (3D multi-start and attitude grid, "
    "global search, map building); 0: the machine's cores. Results are the same for any count";

/// The sections, in file order.
inline const std::vector<std::string>& sections() {
  static const std::vector<std::string> kSections{
      kSharedSensor, "vdt-opt",     "vdt-ekf", "udt",      "pf",
      "active-ekf",  "passive-ekf", "global",  "recovery", kLocalize3d};
  return kSections;
}

/// "vdt-opt, vdt-ekf, ...": the section names for error messages.
inline std::string section_list() {
  std::string known;
  for (const std::string& s : sections()) known += (known.empty() ? "" : ", ") + s;
  return known;
}

inline const char* section_doc(const std::string& section) {
  if (section == kSharedSensor)
    return "the VDT sensor model of every 2D VDT method (vdt-opt, vdt-ekf and its start, the "
           "ekf of active-ekf and passive-ekf), read first: a method's own sensor: keys override "
           "it key by key. Its map_* keys are the map-error model. Not localize3d's (a 3D map: "
           "localize3d.optimizer.sensor)";
  if (section == "vdt-opt") return "optimization localizer on the VDT (thesis 3.2)";
  if (section == "vdt-ekf") return "EKF on the VDT (thesis 3.3)";
  if (section == "udt") return "UDT baselines udt-opt and udt-ekf (chamfer matching)";
  if (section == "active-ekf") return "one reading per scan, the beam pointed by (4.1) (ch. 4)";
  if (section == "passive-ekf") return "one reading per scan, the beam not pointed (ch. 4)";
  if (section == "recovery")
    return "lost detection and kidnapped-robot recovery around vdt-opt and vdt-ekf";
  if (section == "global")
    return "global localization from one scan, --init global (branch and bound; refines with "
           "vdt-opt's settings)";
  if (section == kLocalize3d)
    return "the sequential 3D localizer of `vdtnav localize3d` (vdt_localizer3d.hpp); its "
           "flags --dof, --min-explained, --multi-start, --attitude-sigma override these keys";
  return "particle filter (AMCL's likelihood field)";
}

/// Visits the keys of one section (not the shared sensor: block, which reader and writer treat
/// apart).
template <typename V>
void visit_section(V& v, const std::string& section, LocalizerSettings& s) {
  if (section == "global") visit(v, s.global);
  if (section == "recovery") visit(v, s.recovery);
  if (section == "active-ekf") visit(v, s.active_ekf);
  if (section == "passive-ekf") visit(v, s.passive_ekf);
  if (section == "vdt-opt") visit(v, s.vdt_opt);
  if (section == "vdt-ekf") visit(v, s.vdt_ekf);
  if (section == "udt") visit(v, s.udt);
  if (section == "pf") visit(v, s.pf);
  if (section == kLocalize3d) visit(v, s.localize3d);
}

/// Every VdtSensorModelOptions of a 2D VDT method: what the shared sensor: block reaches. (Not
/// global's optimizer, which make_localizer and --init global replace with vdt-opt's; not
/// localize3d's, a 3D map.)
inline std::vector<VdtSensorModelOptions*> shared_sensor_targets(LocalizerSettings& s) {
  return {&s.vdt_opt.sensor,
          &s.vdt_ekf.sensor,
          &s.vdt_ekf.start.sensor,
          &s.active_ekf.ekf.sensor,
          &s.active_ekf.ekf.start.sensor,
          &s.passive_ekf.ekf.sensor,
          &s.passive_ekf.ekf.start.sensor};
}

}  // namespace vdtnav::config_keys
