// vdtnav_pan_tilt_3d: the thesis's Table 3.4 / Fig. 3.18 study (Dataset 4, section 3.4.4.2). A
// Turtlebot with a LIDAR-Lite v3 point laser on a pan-tilt unit stands still, rolled and pitched
// by an uneven floor, at 3 locations of a 3D map; a 5700-reading sweep is taken at each and the
// 6-DOF pose is estimated by the VDT optimizer (Algorithm 1 on SE(3)) from the initial guesses
// A-D of Table 3.4, with the sweep kept whole and downsampled by 2, 5, 10 and 100. Every cell of
// the table is repeated over independent range-noise seeds.
//
// The map is the CATEC OctoMap of the DLL data set when it is present (or any .bt/.ot given with
// --map), otherwise a generated 3D room (sim::generate_room3d). Writes table.csv, table.md,
// rmse.png (Fig. 3.18) and slices of the 3D VDT to --out; progress goes to stderr, the table to
// stdout.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/pose3.hpp"
#include "vdtnav/estimation/multi_start.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/sensor/observation_set.hpp"
#include "vdtnav/sensor/pan_tilt_unit.hpp"
#include "vdtnav/sensor/point_laser_observations.hpp"
#include "vdtnav/sim/point_laser_simulator.hpp"
#include "vdtnav/sim/ray_casting.hpp"
#include "vdtnav/sim/room3d.hpp"
#include "vdtnav/viz/viz.hpp"
#ifdef VDTNAV_HAVE_OCTOMAP
#include "vdtnav/octomap/octree_map.hpp"
#endif

namespace {

using namespace vdtnav;
using Clock = std::chrono::steady_clock;

constexpr double kPi = 3.14159265358979323846;
/// Where the issue puts the CATEC map, relative to the working directory (the repository root).
const char* const kCatecPath = "../shared/data/3d/dll-catec/catec.bt";

/// Table 3.4: the initial guess is off by +dt in x, y, z and +dr in roll, pitch and yaw.
struct Scenario {
  const char* name;
  double dt;  ///< metres
  double dr;  ///< radians
};
constexpr std::array<Scenario, 4> kScenarios{
    {{"A", 0.05, 0.025}, {"B", 0.1, 0.05}, {"C", 0.2, 0.1}, {"D", 0.4, 0.2}}};
/// Downsampling factors of 3.4.4.2 (1: the whole sweep).
constexpr std::array<int, 5> kFactors{1, 2, 5, 10, 100};
constexpr double kSuccessPosition = 0.1;   ///< metres
constexpr double kSuccessAttitude = 0.05;  ///< radians

/// The world the study runs in: the occupancy the simulator casts rays in, its VDT and the three
/// robot locations.
struct World {
  std::string name;
  OccupancyGrid<3> occupancy;
  std::vector<Pose3> locations;
  std::string how_located;  ///< one line on how the locations were chosen
};

/// One localization attempt.
struct Trial {
  LocalizationStatus status = LocalizationStatus::kTooFewObservations;
  double position_error = 0.0;  ///< metres
  double attitude_error = 0.0;  ///< radians (rotation angle of R_est R_true^T)
  double ms = 0.0;
  int observations = 0;
  int inliers = 0;
  double final_cost = 0.0;
  /// --verbose: the truncated VCD at the estimate and at the truth (multi_start.hpp); an estimate
  /// that scores lower than the truth is a wrong minimum no search could have told apart.
  double tvcd_estimate = 0.0, tvcd_truth = 0.0;
};

/// One cell of Table 3.4 x factors.
struct Cell {
  int trials = 0, converged = 0, success = 0;
  int within = 0;  ///< an estimate (converged or not) within the success thresholds
  double pos_sq = 0.0, att_sq = 0.0, ms = 0.0, observations = 0.0;
  [[nodiscard]] double success_pct() const { return trials ? 100.0 * success / trials : 0.0; }
  [[nodiscard]] double pos_rmse() const {
    return converged ? std::sqrt(pos_sq / converged) : std::numeric_limits<double>::quiet_NaN();
  }
  [[nodiscard]] double att_rmse() const {
    return converged ? std::sqrt(att_sq / converged) : std::numeric_limits<double>::quiet_NaN();
  }
  [[nodiscard]] double ms_mean() const { return trials ? ms / trials : 0.0; }
};

/// \return the initial guess of scenario s: Table 3.4's offsets added to x, y, z and to the ZYX
/// roll, pitch, yaw of the truth. In the 4-DOF mode roll and pitch are the true (IMU) ones.
Pose3 initial_guess(const Pose3& truth, const Scenario& s, bool four_dof) {
  const Eigen::Vector3d t = truth.translation() + Eigen::Vector3d::Constant(s.dt);
  Eigen::Vector3d rpy = rpy_of(truth.linear());
  rpy[2] += s.dr;
  if (!four_dof) {
    rpy[0] += s.dr;
    rpy[1] += s.dr;
  }
  return pose3_from_xyz_rpy(t.x(), t.y(), t.z(), rpy[0], rpy[1], rpy[2]);
}

/// \return the observation set of every k-th reading of the sweep (k = 1: all of them), readings
/// without a return included in the count, as the thesis downsamples the recorded sweep.
ObservationSet3 every_kth_reading(const sim::PointLaserSweep& sweep,
                                  const sim::PointLaserSimOptions& sim, int k) {
  std::vector<PanTiltReading> kept;
  kept.reserve(sweep.readings.size() / static_cast<std::size_t>(k) + 1);
  for (std::size_t i = 0; i < sweep.readings.size(); i += static_cast<std::size_t>(k))
    kept.push_back(sweep.readings[i]);
  ObservationSet3 set = point_laser_observations(kept, sim.calibration, sim.spec);
  for (std::size_t& b : set.beam) b *= static_cast<std::size_t>(k);  // index in the whole sweep
  return set;
}

/// \return the world height of the beam origin at zero pan and tilt (the "sensor height").
double sensor_z(const Pose3& robot, const PanTiltCalibration& calibration) {
  return (robot * pan_tilt_laser_pose(calibration, 0.0, 0.0)).translation().z();
}

#ifdef VDTNAV_HAVE_OCTOMAP
/// Picks `count` robot locations in the free space of an arbitrary 3D map (e.g. an OctoMap of a
/// real building), deterministically from `seed`:
///  - the floor band: the most frequent height of the lowest occupied voxel of a column, +-0.4 m;
///  - a candidate (x, y) is drawn uniformly over the columns whose lowest voxel is in that band
///    (shrunk by 1 m); its floor z_f is the median of those lowest voxels within 0.5 m (>= 5 of
///    them: a real scan's floor is sparse);
///  - free space: |DT_v| > 0.5 m at 0.6, 0.9 and 1.2 m above z_f (a free ball around the robot
///    and its mast) and, at the sensor height, at least 10 of 12 horizontal rays hit the map
///    within 20 m (inside the building, not in the empty margin of the grid);
///  - at least 2 m between locations;
/// and, as sim::uneven_floor_poses does for the generated room, stands the robot there with a
/// uniform yaw, roll and pitch of 1-5 degrees with random signs and its origin 0-5 cm above z_f.
std::vector<Pose3> free_space_locations(const OccupancyGrid<3>& occ, const VdtMap3& vdt, int count,
                                        std::uint32_t seed, std::string* how) {
  const Eigen::Vector3i n = occ.size();
  const double res = occ.resolution();
  std::vector<int> lowest(static_cast<std::size_t>(n.x()) * n.y(), -1);
  std::vector<long> histogram(static_cast<std::size_t>(n.z()), 0);
  for (int j = 0; j < n.y(); ++j)
    for (int i = 0; i < n.x(); ++i)
      for (int k = 0; k < n.z(); ++k)
        if (occ(Eigen::Vector3i(i, j, k))) {
          lowest[static_cast<std::size_t>(j) * n.x() + i] = k;
          ++histogram[static_cast<std::size_t>(k)];
          break;
        }
  const int mode =
      static_cast<int>(std::max_element(histogram.begin(), histogram.end()) - histogram.begin());
  const double floor_mode = occ.cell_center(Eigen::Vector3i(0, 0, mode)).z();
  const auto lowest_z = [&](int i, int j) {
    const int k = lowest[static_cast<std::size_t>(j) * n.x() + i];
    if (k < 0) return std::numeric_limits<double>::quiet_NaN();
    const double z = occ.cell_center(Eigen::Vector3i(i, j, k)).z();
    return std::abs(z - floor_mode) <= 0.4 ? z : std::numeric_limits<double>::quiet_NaN();
  };
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (int j = 0; j < n.y(); ++j)
    for (int i = 0; i < n.x(); ++i)
      if (std::isfinite(lowest_z(i, j))) {
        const Eigen::Vector2d c = occ.cell_center(Eigen::Vector3i(i, j, 0)).head<2>();
        lo = lo.cwiseMin(c);
        hi = hi.cwiseMax(c);
      }
  VDTNAV_CHECK((hi - lo).minCoeff() > 3.0, "pan_tilt_3d: the map has no floor of at least 3 m");
  lo.array() += 1.0;
  hi.array() -= 1.0;

  const auto local_floor = [&](const Eigen::Vector2d& c, double* z_floor) {
    const Eigen::Vector3i a = occ.cell_of(Eigen::Vector3d(c.x() - 0.5, c.y() - 0.5, 0.0));
    const Eigen::Vector3i b = occ.cell_of(Eigen::Vector3d(c.x() + 0.5, c.y() + 0.5, 0.0));
    std::vector<double> zs;
    for (int j = std::max(0, a.y()); j <= std::min(n.y() - 1, b.y()); ++j)
      for (int i = std::max(0, a.x()); i <= std::min(n.x() - 1, b.x()); ++i) {
        const double z = lowest_z(i, j);
        if (std::isfinite(z) &&
            (occ.cell_center(Eigen::Vector3i(i, j, 0)).head<2>() - c).norm() <= 0.5)
          zs.push_back(z);
      }
    if (zs.size() < 5) return false;
    std::nth_element(zs.begin(), zs.begin() + zs.size() / 2, zs.end());
    *z_floor = zs[zs.size() / 2];
    return true;
  };
  const auto is_free = [&](const Eigen::Vector2d& c, double z_floor) {
    for (double h : {0.6, 0.9, 1.2}) {
      bool inside = false;
      const Eigen::Vector3d d = vdt.value(Eigen::Vector3d(c.x(), c.y(), z_floor + h), &inside);
      if (!inside || d.norm() <= 0.5) return false;
    }
    int hits = 0;
    for (int a = 0; a < 12; ++a) {
      const Eigen::Vector3d dir(std::cos(a * kPi / 6), std::sin(a * kPi / 6), 0.0);
      const double r = sim::cast_ray<3>(occ, Eigen::Vector3d(c.x(), c.y(), z_floor + 0.45), dir,
                                        20.0, sim::RaySurface::kCellCentre);
      hits += std::isfinite(r) && r < 20.0 ? 1 : 0;
    }
    return hits >= 10;
  };

  std::mt19937 rng(seed);
  const auto uniform = [&rng](double a, double b) {
    return std::uniform_real_distribution<double>(a, b)(rng);
  };
  const auto signed_tilt = [&] {
    const double m = uniform(1.0 * kPi / 180, 5.0 * kPi / 180);
    return uniform(0.0, 1.0) < 0.5 ? -m : m;
  };
  std::vector<Pose3> poses;
  std::vector<Eigen::Vector2d> places;
  int attempts = 0;
  for (; static_cast<int>(poses.size()) < count; ++attempts) {
    if (attempts >= 20000)
      throw ConfigError("pan_tilt_3d: found only " + std::to_string(poses.size()) + " of " +
                        std::to_string(count) +
                        " free robot locations (|DT_v| > 0.5 m above a floor, 2 m apart)");
    const Eigen::Vector2d c(uniform(lo.x(), hi.x()), uniform(lo.y(), hi.y()));
    if (std::any_of(places.begin(), places.end(),
                    [&](const Eigen::Vector2d& p) { return (p - c).norm() < 2.0; }))
      continue;
    double z_floor = 0.0;
    if (!local_floor(c, &z_floor) || !is_free(c, z_floor)) continue;
    const double yaw = uniform(-kPi, kPi);
    const double roll = signed_tilt(), pitch = signed_tilt();
    const double z = z_floor + uniform(0.0, 0.05);
    places.push_back(c);
    poses.push_back(pose3_from_xyz_rpy(c.x(), c.y(), z, roll, pitch, yaw));
  }
  char line[256];
  std::snprintf(line, sizeof line,
                "chosen automatically (seed %u, %d candidates): floor band %.2f +- 0.4 m, "
                "|DT_v| > 0.5 m from 0.6 to 1.2 m above the local floor, 2 m apart (%.2f m voxels)",
                seed, attempts, floor_mode, res);
  *how = line;
  return poses;
}
#endif  // VDTNAV_HAVE_OCTOMAP

/// |DT_v| on a plane: the points origin + i * du + j * dv, i < nu, j < nv.
Grid<float, 2> vdt_slice(const VdtMap3& vdt, const Eigen::Vector3d& origin,
                         const Eigen::Vector3d& du, const Eigen::Vector3d& dv, int nu, int nv,
                         double cell) {
  Grid<float, 2> out(Eigen::Vector2i(nu, nv), GridFrame<2>(cell, Eigen::Vector2d::Zero()), 0.f);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i)
      out(Eigen::Vector2i(i, j)) = static_cast<float>(vdt.value(origin + i * du + j * dv).norm());
  return out;
}

/// Writes the |DT_v| slices with the robot locations marked: a horizontal one at the mean sensor
/// height (vdt_slice_horizontal.png) and two vertical ones through location 1
/// (vdt_slice_vertical.png).
void write_vdt_slices(const World& world, const VdtMap3& vdt, const PanTiltCalibration& cal,
                      const std::string& out) {
  const double res = vdt.resolution();
  const Eigen::Vector3d lo = vdt.frame().origin();
  const Eigen::Vector3d hi = lo + vdt.size().cast<double>() * res;
  const Eigen::Vector3i n = vdt.size();
  double z = 0.0;
  for (const Pose3& p : world.locations) z += sensor_z(p, cal);
  z /= static_cast<double>(world.locations.size());
  // Colour scale of a slice: 0 to its largest value, at most 2 m (the colour saturates beyond).
  const auto clip = [](const Grid<float, 2>& g) {
    return std::clamp(static_cast<double>(viz::finite_range(g).second), 0.1, 2.0);
  };
  const auto mark = [&](viz::Axes& ax, int u, int v, bool heading) {
    for (std::size_t k = 0; k < world.locations.size(); ++k) {
      const Pose3& p = world.locations[k];
      const Eigen::Vector3d s = (p * pan_tilt_laser_pose(cal, 0.0, 0.0)).translation();
      const viz::Rgb color = viz::kColorCycle[(k + 1) % viz::kColorCycle.size()];
      if (heading) {
        const Eigen::Vector3d f = s + 0.8 * p.linear().col(0);
        ax.line({s[u], f[u]}, {s[v], f[v]}, viz::Style().with_color(color).with_width(3));
      }
      ax.scatter({s[u]}, {s[v]},
                 viz::Style()
                     .with_color(color)
                     .with_marker(viz::Marker::kCircle, 14)
                     .with_label("L" + std::to_string(k + 1)));
    }
  };
  {
    const Grid<float, 2> h =
        vdt_slice(vdt, Eigen::Vector3d(lo.x() + 0.5 * res, lo.y() + 0.5 * res, z),
                  Eigen::Vector3d(res, 0, 0), Eigen::Vector3d(0, res, 0), n.x(), n.y(), res);
    const double w = hi.x() - lo.x(), d = hi.y() - lo.y();
    viz::Figure fig(1400, static_cast<int>(std::clamp(1150.0 * d / w, 500.0, 1600.0)) + 150);
    char title[160];
    std::snprintf(title, sizeof title, "%s: |DT_v| at the mean sensor height z = %.2f m",
                  world.name.c_str(), z);
    fig.title(title);
    auto& ax = fig.axes();
    ax.image(viz::heatmap(h, viz::Colormap::kViridis, 0.0, clip(h)), lo.x(), hi.x(), lo.y(), hi.y())
        .equal_aspect()
        .colorbar(viz::Colormap::kViridis, 0.0, clip(h), "|DT_v| [m]")
        .xlabel("x [m]")
        .ylabel("y [m]");
    mark(ax, 0, 1, true);
    fig.save_png(out + "/vdt_slice_horizontal.png");
  }
  {
    const Eigen::Vector3d s =
        (world.locations.front() * pan_tilt_laser_pose(cal, 0.0, 0.0)).translation();
    const Grid<float, 2> xz =
        vdt_slice(vdt, Eigen::Vector3d(lo.x() + 0.5 * res, s.y(), lo.z() + 0.5 * res),
                  Eigen::Vector3d(res, 0, 0), Eigen::Vector3d(0, 0, res), n.x(), n.z(), res);
    const Grid<float, 2> yz =
        vdt_slice(vdt, Eigen::Vector3d(s.x(), lo.y() + 0.5 * res, lo.z() + 0.5 * res),
                  Eigen::Vector3d(0, res, 0), Eigen::Vector3d(0, 0, res), n.y(), n.z(), res);
    const double hz = hi.z() - lo.z(), wide = std::max(hi.x() - lo.x(), hi.y() - lo.y());
    viz::Figure fig(1400, static_cast<int>(std::clamp(2 * 1150.0 * hz / wide, 300.0, 1600.0)) + 300,
                    2, 1);
    fig.title(world.name + ": vertical |DT_v| slices through location L1");
    char t1[96], t2[96];
    std::snprintf(t1, sizeof t1, "plane y = %.2f m", s.y());
    std::snprintf(t2, sizeof t2, "plane x = %.2f m", s.x());
    auto& a = fig.axes(0, 0);
    a.image(viz::heatmap(xz, viz::Colormap::kViridis, 0.0, clip(xz)), lo.x(), hi.x(), lo.z(),
            hi.z())
        .equal_aspect()
        .colorbar(viz::Colormap::kViridis, 0.0, clip(xz), "|DT_v| [m]")
        .title(t1)
        .xlabel("x [m]")
        .ylabel("z [m]");
    a.scatter({s.x()}, {s.z()},
              viz::Style()
                  .with_color(viz::kColorCycle[1])
                  .with_marker(viz::Marker::kCircle, 14)
                  .with_label("L1 sensor"));
    auto& b = fig.axes(1, 0);
    b.image(viz::heatmap(yz, viz::Colormap::kViridis, 0.0, clip(yz)), lo.y(), hi.y(), lo.z(),
            hi.z())
        .equal_aspect()
        .colorbar(viz::Colormap::kViridis, 0.0, clip(yz), "|DT_v| [m]")
        .title(t2)
        .xlabel("y [m]")
        .ylabel("z [m]");
    b.scatter({s.y()}, {s.z()},
              viz::Style()
                  .with_color(viz::kColorCycle[1])
                  .with_marker(viz::Marker::kCircle, 14)
                  .with_label("L1 sensor"));
    fig.save_png(out + "/vdt_slice_vertical.png");
  }
}

/// Fig. 3.18: RMSE per scenario against the downsampling factor, with the success rate and the
/// solve time (x: log10 of the factor, which the plots cannot put on a log axis themselves).
void write_rmse_figure(const std::vector<std::vector<Cell>>& cells, const std::string& title,
                       const std::string& path) {
  viz::Figure fig(1600, 1100, 2, 2);
  fig.title(title);
  std::vector<double> xs;
  for (int f : kFactors) xs.push_back(std::log10(static_cast<double>(f)));
  const char* xlabel = "log10(factor k), k = 1, 2, 5, 10, 100";
  const viz::Marker markers[4] = {viz::Marker::kCircle, viz::Marker::kSquare,
                                  viz::Marker::kTriangle, viz::Marker::kCross};
  const auto series = [&](viz::Axes& ax, double (Cell::*metric)() const) {
    for (std::size_t s = 0; s < kScenarios.size(); ++s) {
      std::vector<double> ys;
      for (std::size_t f = 0; f < kFactors.size(); ++f) ys.push_back((cells[s][f].*metric)());
      ax.line(xs, ys,
              viz::Style()
                  .with_color(viz::kColorCycle[s])
                  .with_marker(markers[s], 10)
                  .with_label(std::string("scenario ") + kScenarios[s].name));
    }
    ax.xlabel(xlabel);
  };
  series(fig.axes(0, 0), &Cell::pos_rmse);
  fig.axes(0, 0)
      .hline(0.02, viz::Style().with_dashes().with_label("target at factor 1"))
      .title("position RMSE (converged trials)")
      .ylabel("RMSE [m]")
      .legend(viz::LegendLocation::kUpperLeft);
  series(fig.axes(0, 1), &Cell::att_rmse);
  fig.axes(0, 1)
      .hline(0.01, viz::Style().with_dashes().with_label("target at factor 1"))
      .title("attitude RMSE (converged trials)")
      .ylabel("RMSE [rad]")
      .legend(viz::LegendLocation::kUpperLeft);
  series(fig.axes(1, 0), &Cell::success_pct);
  fig.axes(1, 0)
      .title("success: < 0.1 m and < 0.05 rad")
      .ylabel("success [%]")
      .ylim(0.0, 105.0)
      .legend(viz::LegendLocation::kLowerLeft);
  series(fig.axes(1, 1), &Cell::ms_mean);
  fig.axes(1, 1)
      .title("solve time")
      .ylabel("ms per solve")
      .legend(viz::LegendLocation::kUpperRight);
  fig.save_png(path);
}

std::string format_number(double v, const char* fmt) {
  if (!std::isfinite(v)) return "nan";
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Table 3.4 / Fig. 3.18 study: 6-DOF VDT localization of a pan-tilt point laser sweep from "
      "the initial guesses A-D, with the sweep downsampled by 1, 2, 5, 10 and 100"};
  std::string out = "out/pan_tilt_3d", map_path;
  bool room = false;
  int seeds = 20, dof = 6, threads = 2;
  bool verbose = false;
  unsigned seed = 1;
  double resolution = 0.0;
  VdtOptimizerOptions opt;
  // An offline study can afford more iterations than the optimizer's default (25, sized for
  // tracking): on a sparse real octree (the CATEC floor is rings of LiDAR returns) LM takes 30 to
  // 80 steps to converge from guesses B and C, and stopping early reports "not converged".
  opt.max_iterations = 100;
  std::string loss = "none";
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--map", map_path,
                 std::string("OctoMap (.bt/.ot) to run in; default: ") + kCatecPath +
                     " when it exists, else the generated 3D room");
  app.add_flag("--room", room, "use the generated 3D room even when the CATEC map is present");
  app.add_option("--seeds", seeds, "range-noise seeds per location (trials = 3 x seeds per cell)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  app.add_option("--resolution", resolution,
                 "voxel size in metres (0: the map's own, 0.05 m; an OctoMap accepts whole "
                 "multiples of its resolution)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--dof", dof, "6: full 6-DOF; 4: x, y, z, yaw with roll/pitch held at the IMU's")
      ->capture_default_str()
      ->check(CLI::IsMember({4, 6}));
  app.add_option("--seed", seed, "seed of the room, the locations and the noise")
      ->capture_default_str();
  app.add_option("--gate", opt.sensor.gate, "optimizer gate alpha (3.3), metres")
      ->capture_default_str();
  app.add_option("--pyramid", opt.pyramid_levels,
                 "optimizer coarse-to-fine levels (< 0: the optimizer's default)")
      ->capture_default_str();
  app.add_option("--loss", loss, "optimizer robust loss")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "huber", "cauchy"}));
  app.add_option("--loss-scale", opt.loss_scale, "robust loss scale, metres")
      ->capture_default_str();
  app.add_option("--max-iterations", opt.max_iterations, "optimizer iterations per Ceres solve")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000));
  MultiStartOptions multi_start;
  bool single_start = false;
  app.add_flag("--single-start", single_start,
               "one solve from the guess, as the thesis (default: more starts when the solution "
               "leaves readings unexplained, see estimation/multi_start.hpp)");
  app.add_flag("--verbose", verbose, "list every unsuccessful trial on stderr");
  app.add_option("--threads", threads, "worker threads")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  CLI11_PARSE(app, argc, argv);

  try {
    const auto t_start = Clock::now();
    const auto seconds = [&] {
      return std::chrono::duration<double>(Clock::now() - t_start).count();
    };
    std::filesystem::create_directories(out);
    const bool four_dof = dof == 4;
    // LIDAR-Lite v3 (0.05-40 m, sigma 0.025 m) on the Turtlebot-like unit; the default sweep is
    // 100 pans x 57 tilts = 5700 readings, a tilt count coprime to every factor, so every k-th
    // reading still visits all tilts.
    const sim::PointLaserSimOptions sim_options;
    const PanTiltCalibration& cal = sim_options.calibration;

    // ---------------------------------------------------------------- world
    if (map_path.empty() && !room) {
#ifdef VDTNAV_HAVE_OCTOMAP
      if (std::filesystem::exists(kCatecPath)) map_path = kCatecPath;
#else
      if (std::filesystem::exists(kCatecPath))
        std::fprintf(stderr, "[map] %s is present, but this build has no OctoMap front end\n",
                     kCatecPath);
#endif
    }
    World world;
    std::unique_ptr<VdtMap3> vdt;
    if (map_path.empty()) {
      sim::Room3dOptions ro;
      ro.seed = seed;
      if (resolution > 0.0) {
        ro.resolution = resolution;
        ro.wall_thickness = std::max(ro.wall_thickness, 2.0 * resolution);
      }
      std::fprintf(stderr, "[map] generating the 3D room (seed %u, %.3f m voxels)\n", seed,
                   ro.resolution);
      sim::Room3d r = sim::generate_room3d(ro);
      world.name = "generated room";
      sim::UnevenFloorOptions uo;
      uo.seed = seed;
      world.locations = sim::uneven_floor_poses(r, uo);
      world.how_located =
          "sim::uneven_floor_poses (seed " + std::to_string(seed) +
          "): 0.5 m clearance up to 1 m, 2 m apart, roll/pitch 1-5 deg, origin 0-5 cm above the "
          "floor";
      world.occupancy = std::move(r.occupancy);
      std::fprintf(stderr, "[map] building the VDT of %d x %d x %d voxels\n",
                   world.occupancy.size().x(), world.occupancy.size().y(),
                   world.occupancy.size().z());
      vdt = std::make_unique<VdtMap3>(VdtMap3::build(world.occupancy));
    } else {
#ifdef VDTNAV_HAVE_OCTOMAP
      OctreeOccupancyOptions oo;
      oo.resolution = resolution;
      oo.margin = 0.5;  // free border: rays leaving the building end in free space, not the edge
      std::fprintf(stderr, "[map] loading %s\n", map_path.c_str());
      OctreeOccupancy tree = load_octree_occupancy(map_path, oo);
      world.name = std::filesystem::path(map_path).filename().string();
      world.occupancy = std::move(tree.occupancy);
      std::fprintf(stderr,
                   "[map] building the VDT of %d x %d x %d voxels of %.3f m (%zu occupied)\n",
                   world.occupancy.size().x(), world.occupancy.size().y(),
                   world.occupancy.size().z(), world.occupancy.resolution(), tree.num_occupied);
      vdt = std::make_unique<VdtMap3>(VdtMap3::build(world.occupancy));
      world.locations = free_space_locations(world.occupancy, *vdt, 3, seed, &world.how_located);
#else
      std::fprintf(stderr,
                   "error: --map needs the OctoMap front end (vdtnav::octomap), which this build "
                   "does not have; configure with -DVDTNAV_BUILD_FRONTENDS=ON and OctoMap "
                   "installed\n");
      return 2;
#endif
    }
    const Eigen::Vector3i size = world.occupancy.size();
    std::printf("map: %s, %d x %d x %d voxels of %.3f m, VDT %.0f MB (%.1f s)\n",
                world.name.c_str(), size.x(), size.y(), size.z(), world.occupancy.resolution(),
                vdt->memory_bytes() / 1e6, seconds());
    std::printf("robot locations (%s):\n", world.how_located.c_str());
    for (std::size_t k = 0; k < world.locations.size(); ++k) {
      const Pose3& p = world.locations[k];
      const Eigen::Vector3d rpy = rpy_of(p.linear());
      std::printf(
          "  L%zu  x %.3f  y %.3f  z %.3f m  roll %+.2f  pitch %+.2f  yaw %+.1f deg  (sensor at "
          "z %.2f m)\n",
          k + 1, p.translation().x(), p.translation().y(), p.translation().z(), rpy[0] * 180 / kPi,
          rpy[1] * 180 / kPi, rpy[2] * 180 / kPi, sensor_z(p, cal));
    }
    std::fflush(stdout);

    // ---------------------------------------------------------------- trials
    multi_start.enabled = !single_start;
    opt.four_dof = four_dof;
    opt.loss = loss == "huber"    ? RobustLoss::kHuber
               : loss == "cauchy" ? RobustLoss::kCauchy
                                  : RobustLoss::kNone;
    const VdtOptimizer3 optimizer(*vdt, opt);
    const std::size_t n_loc = world.locations.size();
    const std::size_t n_seeds = static_cast<std::size_t>(seeds);
    const std::size_t n_jobs = n_loc * n_seeds;
    const std::size_t per_job = kScenarios.size() * kFactors.size();
    // trials[job][scenario * factors + factor], job = location * seeds + seed
    std::vector<std::vector<Trial>> trials(n_jobs, std::vector<Trial>(per_job));
    std::vector<std::size_t> sweep_returns(n_jobs, 0);
    std::atomic<std::size_t> next{0}, done{0};
    std::atomic<bool> failed{false};
    std::string failure;
    std::mutex failure_mutex;
    const auto work = [&] {
      for (std::size_t job = next++; job < n_jobs && !failed; job = next++) {
        try {
          const std::size_t loc = job / n_seeds, s = job % n_seeds;
          std::seed_seq seq{seed, static_cast<unsigned>(loc), static_cast<unsigned>(s)};
          std::uint32_t noise_seed = 0;
          seq.generate(&noise_seed, &noise_seed + 1);
          const Pose3& truth = world.locations[loc];
          const sim::PointLaserSweep sweep =
              sim::simulate_point_laser_sweep(world.occupancy, truth, sim_options, noise_seed);
          for (std::size_t f = 0; f < kFactors.size(); ++f) {
            const ObservationSet3 obs = every_kth_reading(sweep, sim_options, kFactors[f]);
            if (f == 0) sweep_returns[job] = obs.size();
            for (std::size_t c = 0; c < kScenarios.size(); ++c) {
              const Pose3 guess = initial_guess(truth, kScenarios[c], four_dof);
              const auto t0 = Clock::now();
              const LocalizationResult3 r = solve_multi_start(optimizer, obs, guess, multi_start);
              Trial& t = trials[job][c * kFactors.size() + f];
              t.ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
              t.status = r.status;
              t.position_error = (r.pose.translation() - truth.translation()).norm();
              t.attitude_error = attitude_error(r.pose, truth);
              t.observations = static_cast<int>(obs.size());
              t.inliers = r.inliers;
              t.final_cost = r.final_cost;
              if (verbose) {
                const MultiStartOptions& m = multi_start;
                t.tvcd_estimate =
                    truncated_vcd(optimizer.sensor_model(), obs, r.pose, m.truncation);
                t.tvcd_truth = truncated_vcd(optimizer.sensor_model(), obs, truth, m.truncation);
              }
            }
          }
        } catch (const std::exception& e) {
          const std::lock_guard<std::mutex> lock(failure_mutex);
          if (!failed) failure = e.what();
          failed = true;
        }
        ++done;
      }
    };
    std::fprintf(stderr,
                 "[trials] %zu locations x %d seeds x %zu scenarios x %zu factors = %zu solves "
                 "(%s, %d threads)\n",
                 n_loc, seeds, kScenarios.size(), kFactors.size(), n_jobs * per_job,
                 four_dof ? "4-DOF" : "6-DOF", threads);
    const auto t_trials = Clock::now();
    std::vector<std::thread> pool;
    for (int i = 0; i < threads; ++i) pool.emplace_back(work);
    for (std::size_t shown = 0; shown < n_jobs && !failed;) {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      const std::size_t d = done.load();
      if (d == shown && d < n_jobs) continue;
      shown = d;
      const double el = std::chrono::duration<double>(Clock::now() - t_trials).count();
      std::fprintf(stderr, "\r  sweeps %zu/%zu  solves %zu/%zu  %.1f s (eta %.0f s)   ", d, n_jobs,
                   d * per_job, n_jobs * per_job, el,
                   d ? el * static_cast<double>(n_jobs - d) / static_cast<double>(d) : 0.0);
    }
    for (auto& t : pool) t.join();
    std::fprintf(stderr, "\n");
    if (failed) throw Error(failure);
    const double trials_s = std::chrono::duration<double>(Clock::now() - t_trials).count();

    // ---------------------------------------------------------------- table
    std::vector<std::vector<Cell>> cells(kScenarios.size(), std::vector<Cell>(kFactors.size()));
    for (std::size_t job = 0; job < n_jobs; ++job)
      for (std::size_t c = 0; c < kScenarios.size(); ++c)
        for (std::size_t f = 0; f < kFactors.size(); ++f) {
          const Trial& t = trials[job][c * kFactors.size() + f];
          Cell& cell = cells[c][f];
          ++cell.trials;
          cell.ms += t.ms;
          cell.observations += t.observations;
          const bool ok = t.status == LocalizationStatus::kConverged &&
                          t.position_error < kSuccessPosition &&
                          t.attitude_error < kSuccessAttitude;
          if (verbose && !ok)
            std::fprintf(stderr,
                         "  unsuccessful: L%zu seed %zu scenario %s factor %d: %s, %.3f m, "
                         "%.3f rad, %d inliers of %d readings, d_VCD %.4f m^2, truncated VCD "
                         "%.4f (truth %.4f)\n",
                         job / n_seeds + 1, job % n_seeds, kScenarios[c].name, kFactors[f],
                         to_string(t.status), t.position_error, t.attitude_error, t.inliers,
                         t.observations, t.final_cost, t.tvcd_estimate, t.tvcd_truth);
          const bool estimated = t.status == LocalizationStatus::kConverged ||
                                 t.status == LocalizationStatus::kNotConverged;
          if (estimated && t.position_error < kSuccessPosition &&
              t.attitude_error < kSuccessAttitude)
            ++cell.within;
          if (t.status != LocalizationStatus::kConverged) continue;
          ++cell.converged;
          cell.pos_sq += t.position_error * t.position_error;
          cell.att_sq += t.attitude_error * t.attitude_error;
          if (t.position_error < kSuccessPosition && t.attitude_error < kSuccessAttitude)
            ++cell.success;
        }
    double returns = 0.0;
    for (std::size_t r : sweep_returns) returns += static_cast<double>(r);
    returns /= static_cast<double>(n_jobs);

    std::ofstream csv(out + "/table.csv");
    csv << "scenario,factor,trials,success_pct,pos_rmse_m,att_rmse_rad,ms_mean\n";
    std::ofstream md(out + "/table.md");
    md << "## Table 3.4 / Fig. 3.18: pan-tilt point laser, " << (four_dof ? "4" : "6")
       << "-DOF VDT optimization (" << world.name << ")\n\n";
    {
      char buf[512];
      std::snprintf(buf, sizeof buf,
                    "Map: %s, %d x %d x %d voxels of %.3f m. Sweep: %zu readings (%d pans x %d "
                    "tilts, LIDAR-Lite v3: 0.05-40 m, sigma_r = %.3f m), %.0f returns on average. "
                    "%d noise seeds x %zu locations = %zu trials per cell.\n\n",
                    world.name.c_str(), size.x(), size.y(), size.z(), world.occupancy.resolution(),
                    sim_options.pattern.size(), sim_options.pattern.pan_steps,
                    sim_options.pattern.tilt_steps, sim_options.spec.sigma_range, returns, seeds,
                    n_loc, n_jobs);
      md << buf;
    }
    md << "Robot locations (" << world.how_located << "):\n\n";
    for (std::size_t k = 0; k < n_loc; ++k) {
      const Pose3& p = world.locations[k];
      const Eigen::Vector3d rpy = rpy_of(p.linear()) * 180 / kPi;
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "- L%zu: x %.3f, y %.3f, z %.3f m; roll %+.2f, pitch %+.2f, yaw %+.1f deg\n",
                    k + 1, p.translation().x(), p.translation().y(), p.translation().z(), rpy[0],
                    rpy[1], rpy[2]);
      md << buf;
    }
    md << "\nInitial guess: the truth plus Table 3.4's offset in x, y, z and in "
       << (four_dof ? "yaw (roll and pitch held at the true IMU values)" : "roll, pitch, yaw")
       << ": A +0.05 m / +0.025 rad, B 0.1 / 0.05, C 0.2 / 0.1, D 0.4 / 0.2. Factor k keeps every "
          "k-th reading of the sweep.\n\n"
          "Definitions: *converged* = the optimizer returned status `converged`; *success* = "
          "converged and within 0.1 m (position) and 0.05 rad (attitude, the rotation angle of "
          "R_est R_true^T) of the truth, in % of all trials; *within %* = the same thresholds "
          "whatever the status, as long as the optimizer produced an estimate (converged or not "
          "converged); the RMSEs (position: |t_est - t_true|, attitude: that rotation angle) are "
          "over the converged trials, successful or not; readings used = mean returns kept after "
          "downsampling; ms = mean wall time of one solve.\n\n"
          "| scenario | factor | readings used | trials | converged | success % | within % | "
          "pos RMSE (m) | att RMSE (rad) | ms mean |\n|---|---|---|---|---|---|---|---|---|---|\n";
    std::printf("\n%-8s %6s %8s %6s %9s %9s %12s %13s %8s\n", "scenario", "factor", "readings",
                "trials", "converged", "success%", "pos RMSE (m)", "att RMSE (rad)", "ms mean");
    for (std::size_t c = 0; c < kScenarios.size(); ++c)
      for (std::size_t f = 0; f < kFactors.size(); ++f) {
        const Cell& x = cells[c][f];
        const double used = x.observations / x.trials;
        const std::string pos = format_number(x.pos_rmse(), "%.6f");
        const std::string att = format_number(x.att_rmse(), "%.6f");
        csv << kScenarios[c].name << ',' << kFactors[f] << ',' << x.trials << ','
            << format_number(x.success_pct(), "%.2f") << ',' << pos << ',' << att << ','
            << format_number(x.ms_mean(), "%.3f") << '\n';
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "| %s | %d | %.0f | %d | %d | %.1f | %.1f | %s | %s | %.2f |\n",
                      kScenarios[c].name, kFactors[f], used, x.trials, x.converged, x.success_pct(),
                      100.0 * x.within / x.trials, format_number(x.pos_rmse(), "%.4f").c_str(),
                      format_number(x.att_rmse(), "%.4f").c_str(), x.ms_mean());
        md << buf;
        std::printf("%-8s %6d %8.0f %6d %9d %9.1f %12s %13s %8.2f\n", kScenarios[c].name,
                    kFactors[f], used, x.trials, x.converged, x.success_pct(),
                    format_number(x.pos_rmse(), "%.4f").c_str(),
                    format_number(x.att_rmse(), "%.4f").c_str(), x.ms_mean());
      }
    md << "\nFigures: `rmse.png` (Fig. 3.18), `vdt_slice_horizontal.png`, "
          "`vdt_slice_vertical.png`.\n";

    // ---------------------------------------------------------------- figures
    std::fprintf(stderr, "[figures] writing PNGs to %s\n", out.c_str());
    write_rmse_figure(cells,
                      "Fig. 3.18: " + std::string(four_dof ? "4" : "6") + "-DOF RMSE, " +
                          world.name + ", " + std::to_string(n_jobs) + " trials per point",
                      out + "/rmse.png");
    write_vdt_slices(world, *vdt, cal, out);
    std::printf(
        "\n%.1f s in all (trials %.1f s on %d threads); wrote %s/table.csv, table.md, "
        "rmse.png, vdt_slice_horizontal.png, vdt_slice_vertical.png\n",
        seconds(), trials_s, threads, out.c_str());
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
