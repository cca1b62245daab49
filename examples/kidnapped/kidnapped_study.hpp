#pragma once
// The global localization study of the kidnapped example beyond main(): its maps and their scans
// (cases.cpp), branch and bound against random sampling on them (global_trials.cpp) and the
// kidnapping runs on them (kidnap_runs.cpp).
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "kidnapping.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/map/vdt_map.hpp"

namespace study {

/// One map of the study, its trial scans with their true poses, and its drive.
struct Case {
  std::string map, scans;  ///< map name; "simulated" or "real"
  unsigned id = 0;         ///< the map's place in the full list (seeds do not depend on --maps)
  vdtnav::OccupancyGrid<2> grid;
  std::vector<vdtnav::ScanPoints> observations;
  std::vector<vdtnav::Pose2> truth;
  kidnap::Drive drive;  ///< the drive for the kidnappings (simulated when empty)
  /// The localizers' settings: exact_map_settings() on the generated floor plan, the defaults
  /// (log_settings()) on real logs.
  vdtnav::LocalizerSettings settings = vdtnav::exact_map_settings();
};

/// The maps: the generated floor plan (`seed`) and, under `data` when found, the hospital section,
/// fetch-office and the Intel lab (its map from the corrected scans, `trials` of its real scans at
/// random times, its drive with the raw odometry); each with its place in this list as its id.
std::vector<Case> load_cases(const std::string& data, unsigned seed, int trials);

/// Random free poses at least `clearance` from the map, scans simulated there (UTM-30LX).
void simulate(Case& c, const vdtnav::VdtMap2& map, int trials, std::uint32_t seed);

/// The `q` quantile of `v` (the nearest rank); 0 when empty.
double quantile(std::vector<double> v, double q);

/// Branch and bound's time per scan, binned (times.png).
struct Histogram {
  std::vector<double> centres, counts;
};

/// Branch and bound against random sampling (at branch and bound's time on each scan) on the
/// trial scans of `c`: the rows of table.csv and table.md, the printed summary,
/// <map>_success.png; returns branch and bound's time histogram.
Histogram global_trials(const Case& c, const vdtnav::VdtMap2& map, unsigned seed,
                        const std::string& out, std::ofstream& csv, std::ofstream& md);

/// The kidnapped robot on the drive of `c` (simulated first when it has none): vdt-opt and
/// vdt-ekf, each inside its lost detection and recovery; the rows of kidnap.csv (vdt-opt) and
/// kidnap.md, the printed summary, <map>_kidnap.png (vdt-opt).
void kidnap_runs(Case& c, const vdtnav::VdtMap2& map, const kidnap::Options& ko, unsigned seed,
                 const std::string& out, std::ofstream& kcsv, std::ofstream& kmd);

}  // namespace study
