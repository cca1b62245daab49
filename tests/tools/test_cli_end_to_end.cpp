// `vdtnav map`, `vdtnav localize` and `vdtnav eval` end to end on a short simulated CARMEN log:
// the map is built from the log's (true) poses, the log's odometry fields drift like wheel
// odometry, and the localized trajectory is checked against the simulator's ground truth, which
// the test evaluates itself (independently of `vdtnav eval`, whose JSON must agree with it). Bad
// inputs fail with the message a user needs (asserted on the text, not only the exit code).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "cli_runner.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/relations.hpp"
#include "vdtnav/io/tum_trajectory.hpp"
#include "vdtnav/mapping/uncertain_map_file.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/sim/route_planner.hpp"
#include "vdtnav/sim/trajectory.hpp"

namespace vdtnav {
namespace {

constexpr int kBeams = 361;     // FLASER: n beams over 180 degrees, pi / n apart
constexpr double kT0 = 1000.0;  // the log's time base

struct Fixture {
  std::filesystem::path dir;
  sim::SimulatedRun run;
};

using test::contains;
using test::files_in;
using test::read_all;
using test::run_cli;

/// A simulated run of 150 scans at 2 Hz through the generated floor plan, written as a CARMEN
/// log whose FLASER poses are the truth and whose odometry fields are dead reckoning.
const Fixture& fixture() {
  static const Fixture f = [] {
    Fixture x;
    // One folder per process: ctest runs the two tests in parallel processes.
    x.dir = std::filesystem::path(VDTNAV_TEST_TMP) / ("cli_" + std::to_string(::getpid()));
    std::filesystem::create_directories(x.dir);
    const sim::FloorPlan plan = sim::generate_floor_plan({});
    const std::vector<Eigen::Vector2d> path = sim::plan_tour(plan.occupancy, 4, 0.4, 5);
    sim::TrajectoryOptions to;
    to.min_steps = 1;
    const std::vector<sim::TimedPose> full = sim::follow_path(path, plan.occupancy, to);
    std::vector<sim::TimedPose> part;
    for (std::size_t k = 0; k < full.size() && part.size() < 150; k += 20) part.push_back(full[k]);
    // FLASER geometry (beam i at -pi/2 + i pi/n): the symmetric simulated fan turned by the mount.
    sim::LidarOptions lidar;
    lidar.angular_resolution = kPi / kBeams;
    lidar.fov = (kBeams - 1) * lidar.angular_resolution;
    lidar.mount = Pose2(0.0, 0.0, -0.5 * lidar.angular_resolution);
    lidar.range_max = 30.0;
    sim::NoiseProfile noise = sim::NoiseProfile::table_3_2_sigma();
    noise.sigma_w = 0.05;  // drifting odometry: the localizer must correct it
    x.run = sim::simulate_run(plan.occupancy, part, lidar, noise, 11);

    CarmenLog log;
    Pose2 odom = x.run.truth[0];
    for (std::size_t k = 0; k < x.run.size(); ++k) {
      if (k > 0) odom = compose(odom, x.run.odometry[k].delta);
      CarmenLaser l;
      l.time = kT0 + x.run.times[k];
      l.ipc_time = l.time;
      l.pose = x.run.truth[k];
      l.odom = odom;
      l.scan = x.run.scans[k];
      l.scan.mount = Pose2::Zero();
      set_flaser_geometry(kBeams, l.scan);
      log.lasers.push_back(l);
    }
    save_carmen_log((x.dir / "run.log").string(), log);
    std::vector<StampedPose3> truth;
    std::vector<Relation> relations;
    for (std::size_t k = 0; k < x.run.size(); ++k) {
      truth.push_back({kT0 + x.run.times[k], pose3_from_pose2(x.run.truth[k])});
      if (k + 5 < x.run.size()) {
        relations.push_back({kT0 + x.run.times[k], kT0 + x.run.times[k + 5],
                             between(x.run.truth[k], x.run.truth[k + 5])});
      }
    }
    save_tum_trajectory((x.dir / "truth.tum").string(), truth);
    save_relations((x.dir / "truth.relations").string(), relations);
    return x;
  }();
  return f;
}

/// A log of `n` scans in which no beam returns (every range beyond --max-range), from `pose`.
void write_no_return_log(const std::filesystem::path& path, const Pose2& pose, int n) {
  CarmenLog log;
  for (int k = 0; k < n; ++k) {
    CarmenLaser l;
    l.time = l.ipc_time = kT0 + 0.5 * k;
    l.pose = l.odom = pose;
    l.scan.ranges.assign(kBeams, 81.9);
    set_flaser_geometry(kBeams, l.scan);
    log.lasers.push_back(l);
  }
  save_carmen_log(path.string(), log);
}

/// The value of `"key": number` after the first occurrence of `section` in a JSON text.
double json_number(const std::string& js, const std::string& section, const std::string& key) {
  std::size_t p = js.find(section);
  if (p == std::string::npos) return std::nan("");
  p = js.find("\"" + key + "\":", p);
  if (p == std::string::npos) return std::nan("");
  return std::stod(js.substr(p + key.size() + 3));
}

TEST(CliEndToEnd, MapLocalizeEvalRecoverTheSimulatedTrajectory) {
  const Fixture& f = fixture();
  const std::filesystem::path d = f.dir;
  ASSERT_EQ(run_cli("map --log " + (d / "run.log").string() + " --resolution 0.05 --out " +
                        (d / "map").string() + " --quiet",
                    d / "map.txt"),
            0)
      << read_all(d / "map.txt");
  for (const char* ext : {".yaml", ".pgm", ".vdt"}) {
    EXPECT_TRUE(std::filesystem::exists(d / (std::string("map") + ext))) << ext;
  }
  ASSERT_EQ(run_cli("localize --map " + (d / "map.yaml").string() + " --log " +
                        (d / "run.log").string() + " --method vdt-opt --all-poses --out " +
                        (d / "est.tum").string() + " --cov " + (d / "est_cov.csv").string(),
                    d / "localize.txt"),
            0)
      << read_all(d / "localize.txt");

  // --all-poses: one TUM line per scan, stamped in the log's time base, close to the truth.
  const TumTrajectory est = load_tum_trajectory((d / "est.tum").string());
  ASSERT_EQ(est.poses.size(), f.run.size());
  double sq = 0.0, dead_reckoning_sq = 0.0;
  Pose2 odom = f.run.truth[0];
  for (std::size_t k = 0; k < f.run.size(); ++k) {
    EXPECT_NEAR(est.poses[k].t, kT0 + f.run.times[k], 1e-6);
    const Pose2 p = pose2_from_pose3(est.poses[k].pose);
    sq += (p.head<2>() - f.run.truth[k].head<2>()).squaredNorm();
    if (k > 0) odom = compose(odom, f.run.odometry[k].delta);
    dead_reckoning_sq += (odom.head<2>() - f.run.truth[k].head<2>()).squaredNorm();
  }
  const double rmse = std::sqrt(sq / static_cast<double>(f.run.size()));
  const double dead_reckoning = std::sqrt(dead_reckoning_sq / static_cast<double>(f.run.size()));
  EXPECT_LT(rmse, 0.05);  // measured 0.029 m: a map built from 0.02 m-noise scans at 0.05 m
  EXPECT_GT(dead_reckoning, 10.0 * rmse);  // the odometry alone would not do

  // --init global: no initial pose; the first scans that localize without ambiguity start the
  // track, the ones before are not written, and the track matches the truth as well.
  ASSERT_EQ(
      run_cli("localize --map " + (d / "map.yaml").string() + " --log " + (d / "run.log").string() +
                  " --method vdt-opt --init global --all-poses --out " +
                  (d / "global.tum").string(),
              d / "global.txt"),
      0)
      << read_all(d / "global.txt");
  EXPECT_TRUE(contains(read_all(d / "global.txt"), "--init global, scan "))
      << read_all(d / "global.txt");
  const TumTrajectory global = load_tum_trajectory((d / "global.tum").string());
  ASSERT_GE(global.poses.size(), f.run.size() - 10);
  const std::size_t skipped = f.run.size() - global.poses.size();
  double global_sq = 0.0;
  for (std::size_t k = 0; k < global.poses.size(); ++k) {
    EXPECT_NEAR(global.poses[k].t, kT0 + f.run.times[k + skipped], 1e-6);
    global_sq +=
        (pose2_from_pose3(global.poses[k].pose).head<2>() - f.run.truth[k + skipped].head<2>())
            .squaredNorm();
  }
  EXPECT_LT(std::sqrt(global_sq / static_cast<double>(global.poses.size())), 0.05);
  // The same trajectory, byte for byte, at one thread and at three (--threads: the global
  // search's roots, descents, batches and refinements on the pool).
  for (const int t : {1, 3}) {
    const std::string out = "global_t" + std::to_string(t);
    ASSERT_EQ(
        run_cli("localize --map " + (d / "map.yaml").string() + " --log " +
                    (d / "run.log").string() + " --method vdt-opt --init global --all-poses " +
                    "--threads " + std::to_string(t) + " --out " + (d / (out + ".tum")).string(),
                d / (out + ".txt")),
        0)
        << read_all(d / (out + ".txt"));
    EXPECT_EQ(read_all(d / (out + ".tum")), read_all(d / "global.tum")) << t << " threads";
  }

  // The pose table: the header of the issue, one row per scan whatever its status, the status and
  // explained fraction, a positive definite covariance where converged.
  std::ifstream cov(d / "est_cov.csv");
  std::string line;
  std::getline(cov, line);
  EXPECT_EQ(line, "t,status,explained,xx,xy,xt,yy,yt,tt");
  std::size_t rows = 0, with_covariance = 0;
  std::vector<double> converged_times, published_times;  // published: converged or bridged
  while (std::getline(cov, line)) {
    std::vector<std::string> tok;
    std::stringstream s(line);
    for (std::string t; std::getline(s, t, ',');) tok.push_back(t);
    ASSERT_EQ(tok.size(), 9u) << line;
    EXPECT_NEAR(std::stod(tok[0]), est.poses[rows].t, 1e-6) << line;
    const std::string& status = tok[1];
    EXPECT_TRUE(status == "converged" || status == "not_converged" || status == "refused" ||
                status == "too_few_observations" || status == "diverged" || status == "lost" ||
                status == "bridged")
        << line;
    if (status == "converged" || status == "bridged") published_times.push_back(std::stod(tok[0]));
    const double explained = std::stod(tok[2]);
    if (status == "converged") {
      converged_times.push_back(std::stod(tok[0]));
      EXPECT_GE(explained, 0.5) << line;  // a right pose on the map of the same run
      EXPECT_LE(explained, 1.0) << line;
    }
    Eigen::Matrix3d c;
    c << std::stod(tok[3]), std::stod(tok[4]), std::stod(tok[5]), std::stod(tok[4]),
        std::stod(tok[6]), std::stod(tok[7]), std::stod(tok[5]), std::stod(tok[7]),
        std::stod(tok[8]);
    if (c.allFinite()) {
      ++with_covariance;
      EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(c).eigenvalues().minCoeff(), 0.0)
          << line;
    }
    ++rows;
  }
  EXPECT_EQ(rows, f.run.size());
  EXPECT_GT(with_covariance, f.run.size() * 9 / 10);
  EXPECT_GT(converged_times.size(), f.run.size() / 2);

  // Without --all-poses the TUM file holds exactly the converged and bridged scans' poses
  // (published_by_default()), the same ones.
  ASSERT_EQ(
      run_cli("localize --map " + (d / "map.yaml").string() + " --log " + (d / "run.log").string() +
                  " --method vdt-opt --quiet --out " + (d / "usable.tum").string(),
              d / "usable.txt"),
      0)
      << read_all(d / "usable.txt");
  const TumTrajectory usable = load_tum_trajectory((d / "usable.tum").string());
  ASSERT_EQ(usable.poses.size(), published_times.size());
  for (std::size_t k = 0, j = 0; k < usable.poses.size(); ++k) {
    EXPECT_NEAR(usable.poses[k].t, published_times[k], 1e-6);
    while (j < est.poses.size() && est.poses[j].t < usable.poses[k].t - 1e-9) ++j;
    ASSERT_LT(j, est.poses.size());
    EXPECT_TRUE(usable.poses[k].pose.isApprox(est.poses[j].pose, 1e-12)) << k;
  }
  // --accept-status adds statuses; an unknown one is a usage error (exit 2) that writes nothing.
  EXPECT_EQ(
      run_cli("localize --map " + (d / "map.yaml").string() + " --log " + (d / "run.log").string() +
                  " --quiet --accept-status converged,lots --out " + (d / "never.tum").string(),
              d / "never.txt"),
      2);
  EXPECT_TRUE(contains(read_all(d / "never.txt"), "--accept-status: unknown status 'lots'"))
      << read_all(d / "never.txt");
  EXPECT_FALSE(std::filesystem::exists(d / "never.tum"));

  // `vdtnav eval` against the reference and the relations: its unaligned ATE is the test's own.
  ASSERT_EQ(run_cli("eval --traj " + (d / "est.tum").string() + " --reference " +
                        (d / "truth.tum").string() + " --cov " + (d / "est_cov.csv").string() +
                        " --relations " + (d / "truth.relations").string() + " --json-out " +
                        (d / "eval.json").string(),
                    d / "eval.txt"),
            0)
      << read_all(d / "eval.txt");
  const std::string js = read_all(d / "eval.json");
  EXPECT_NEAR(json_number(js, "\"ate_trans_m\"", "rmse"), rmse, 1e-6) << js;
  EXPECT_NEAR(json_number(js, "\"ate_trans_m\"", "count"), static_cast<double>(f.run.size()), 0.5);
  EXPECT_NEAR(json_number(js, "\"relations\"", "used"), static_cast<double>(f.run.size() - 5), 0.5);
  EXPECT_LT(json_number(js, "\"relations\"", "trans_mean_m"), 0.04);  // measured 0.020 m
  // The relation NEES: every relation's ends are scans with a covariance but a few.
  EXPECT_NEAR(json_number(js, "\"relation_nees\"", "used") +
                  json_number(js, "\"relation_nees\"", "skipped_no_covariance"),
              static_cast<double>(f.run.size() - 5), 0.5)
      << js;
  EXPECT_GT(json_number(js, "\"relation_nees\"", "used"), 0.9 * (f.run.size() - 5)) << js;
  EXPECT_GT(json_number(js, "\"relation_nees\"", "mean"), 0.0) << js;
  EXPECT_GE(json_number(js, "\"relation_nees\"", "fraction_inside"), 0.0) << js;
  EXPECT_TRUE(contains(read_all(d / "eval.txt"), "relation NEES (")) << read_all(d / "eval.txt");
}

// `map --uncertain` writes the uncertain map file of the log's first 20 s; every method localizes
// on it (`localize --map X.umap`), the VDT methods with the map's covariance in the one they
// report; the same map from a TUM trajectory of the same poses (`--poses`) is the same file.
TEST(CliEndToEnd, UncertainMapFileFromTheLogLocalizesEveryMethod) {
  const Fixture& f = fixture();
  const std::filesystem::path d = f.dir;
  const std::string window = " --to " + std::to_string(kT0 + 20.0);
  ASSERT_EQ(run_cli("map --log " + (d / "run.log").string() + " --resolution 0.05 --out " +
                        (d / "umap").string() + window +
                        " --uncertain --pose-sigma 0.02,0.02,0.005 --quiet",
                    d / "umap.txt"),
            0)
      << read_all(d / "umap.txt");
  EXPECT_TRUE(contains(read_all(d / "umap.txt"), "wrote " + (d / "umap").string() + ".umap"))
      << read_all(d / "umap.txt");
  for (const char* ext : {".yaml", ".pgm", ".vdt", ".umap"}) {
    EXPECT_TRUE(std::filesystem::exists(d / (std::string("umap") + ext))) << ext;
  }
  ASSERT_EQ(
      run_cli("map --log " + (d / "run.log").string() + " --resolution 0.05 --out " +
                  (d / "umap_tum").string() + window + " --poses " + (d / "truth.tum").string() +
                  " --uncertain --pose-sigma 0.02,0.02,0.005 --quiet",
              d / "umap_tum.txt"),
      0)
      << read_all(d / "umap_tum.txt");
  {
    // The TUM file holds the poses to its printed digits: the same map within a millimetre.
    const mapping::UncertainMapFile a = mapping::load_uncertain_map((d / "umap.umap").string());
    const mapping::UncertainMapFile b = mapping::load_uncertain_map((d / "umap_tum.umap").string());
    ASSERT_EQ(a.map.band_cells(), b.map.band_cells());
    const auto& pts = a.map.observed_points();
    int compared = 0;
    for (std::size_t k = 0; k < pts.size(); k += 17) {
      const mapping::UncertainMapSample sa = a.map.evaluate(pts[k]), sb = b.map.evaluate(pts[k]);
      if (!sa.inside || !sb.inside) continue;
      EXPECT_LT((sa.value - sb.value).norm(), 1e-3);
      ++compared;
    }
    EXPECT_GT(compared, 100);
  }

  const auto localize = [&](const std::string& map, const std::string& method,
                            const std::string& out) {
    EXPECT_EQ(
        run_cli("localize --map " + (d / map).string() + " --log " + (d / "run.log").string() +
                    window + " --method " + method + " --all-poses --out " +
                    (d / (out + ".tum")).string() + " --cov " + (d / (out + ".csv")).string(),
                d / (out + ".txt")),
        0)
        << read_all(d / (out + ".txt"));
    const TumTrajectory est = load_tum_trajectory((d / (out + ".tum")).string());
    double sq = 0.0;
    for (std::size_t k = 0; k < est.poses.size(); ++k) {
      sq +=
          (pose2_from_pose3(est.poses[k].pose).head<2>() - f.run.truth[k].head<2>()).squaredNorm();
    }
    EXPECT_GE(est.poses.size(), 40u) << method;
    return std::sqrt(sq / static_cast<double>(std::max<std::size_t>(est.poses.size(), 1)));
  };
  for (const std::string method : {"vdt-opt", "vdt-ekf", "udt-opt", "pf"}) {
    EXPECT_LT(localize("umap.umap", method, "u_" + method), 0.08) << method;
  }
  EXPECT_TRUE(contains(read_all(d / "u_vdt-opt.txt"), "uncertain map: h = "))
      << read_all(d / "u_vdt-opt.txt");
  // The map's covariance joins vdt-opt's: the same scans mapped with a stated pose noise five
  // times larger give a map whose covariance is larger, and the poses localized on it report a
  // larger covariance.
  ASSERT_EQ(run_cli("map --log " + (d / "run.log").string() + " --resolution 0.05 --out " +
                        (d / "umap_noisy").string() + window +
                        " --uncertain --pose-sigma 0.1,0.1,0.025 --quiet",
                    d / "umap_noisy.txt"),
            0)
      << read_all(d / "umap_noisy.txt");
  (void)localize("umap_noisy.umap", "vdt-opt", "n_vdt-opt");
  const auto mean_position_variance = [&](const std::string& csv) {
    std::ifstream in(d / csv);
    std::string line;
    std::getline(in, line);
    double sum = 0.0;
    int n = 0;
    while (std::getline(in, line)) {
      std::vector<std::string> c;
      std::stringstream ss(line);
      for (std::string cell; std::getline(ss, cell, ',');) c.push_back(cell);
      if (c.size() != 9 || c[1] != "converged") continue;
      sum += std::stod(c[3]) + std::stod(c[6]);
      ++n;
    }
    EXPECT_GT(n, 30) << csv;
    return sum / std::max(n, 1);
  };
  EXPECT_GT(mean_position_variance("n_vdt-opt.csv"), 3.0 * mean_position_variance("u_vdt-opt.csv"));
}

TEST(CliEndToEnd, AStartFarFromTheTruthIsFoundLostAndRecovered) {
  // The robot is not where --init says (a kidnapping before the first scan): --recover (the
  // default) finds the scans unexplained, re-acquires by global localization and then tracks the
  // truth; --no-recover reports the scans lost and never claims a converged pose there.
  const Fixture& f = fixture();
  const std::filesystem::path d = f.dir / "recover";
  std::filesystem::create_directories(d);
  ASSERT_EQ(run_cli("map --log " + (f.dir / "run.log").string() + " --resolution 0.05 --out " +
                        (d / "map").string() + " --quiet",
                    d / "map.txt"),
            0)
      << read_all(d / "map.txt");
  Pose2 wrong = f.run.truth[0];
  for (std::size_t k = 0; k < f.run.size(); ++k) {  // the scan pose farthest from the start
    if ((f.run.truth[k].head<2>() - f.run.truth[0].head<2>()).norm() >
        (wrong.head<2>() - f.run.truth[0].head<2>()).norm())
      wrong = f.run.truth[k];
  }
  ASSERT_GT((wrong.head<2>() - f.run.truth[0].head<2>()).norm(), 5.0);
  char init[128];
  std::snprintf(init, sizeof init, "%.3f,%.3f,%.3f", wrong.x(), wrong.y(), wrong[2]);
  const std::string common = "localize --map " + (d / "map.yaml").string() + " --log " +
                             (f.dir / "run.log").string() + " --method vdt-opt --quiet --init " +
                             init + " --init-sigma 0.05,0.05,0.02";
  ASSERT_EQ(
      run_cli(common + " --recover --all-poses --out " + (d / "rec.tum").string(), d / "rec.txt"),
      0)
      << read_all(d / "rec.txt");
  const std::string rec_text = read_all(d / "rec.txt");
  EXPECT_TRUE(contains(rec_text, "re-acquired              1")) << rec_text;
  const TumTrajectory rec = load_tum_trajectory((d / "rec.tum").string());
  ASSERT_EQ(rec.poses.size(), f.run.size());
  std::size_t first_right = rec.poses.size();
  for (std::size_t k = 0; k < rec.poses.size(); ++k) {
    const Pose2 p = pose2_from_pose3(rec.poses[k].pose);
    const bool right = (p.head<2>() - f.run.truth[k].head<2>()).norm() < 0.3;
    if (right && first_right == rec.poses.size()) first_right = k;
    if (first_right < rec.poses.size()) {
      EXPECT_TRUE(right) << "scan " << k << " after re-acquisition at " << first_right;
    }
  }
  EXPECT_LE(first_right, 20U);  // a window of 5 scans, then one acquisition

  // Never re-acquired, never converged: the run completes with exit 3.
  ASSERT_EQ(run_cli(common + " --no-recover --out " + (d / "norec.tum").string() + " --cov " +
                        (d / "norec.csv").string(),
                    d / "norec.txt"),
            3)
      << read_all(d / "norec.txt");
  const std::string norec_text = read_all(d / "norec.txt");
  EXPECT_TRUE(contains(norec_text, "  lost  ")) << norec_text;
  EXPECT_FALSE(contains(norec_text, "re-acquired")) << norec_text;
  // --strict: the scans lost before the re-acquisition make it exit 3, the outputs written (the
  // same trajectory as without --strict).
  EXPECT_EQ(run_cli(common + " --recover --all-poses --strict --out " + (d / "strict.tum").string(),
                    d / "strict.txt"),
            3)
      << read_all(d / "strict.txt");
  EXPECT_EQ(read_all(d / "strict.tum"), read_all(d / "rec.tum"));
  EXPECT_TRUE(contains(read_all(d / "strict.txt"), "--strict: ")) << read_all(d / "strict.txt");
  EXPECT_TRUE(std::filesystem::exists(d / "strict.tum"));
  // --recover and --no-recover together: a usage error.
  EXPECT_EQ(
      run_cli(common + " --recover --no-recover --out " + (d / "x.tum").string(), d / "both.txt"),
      2);
}

TEST(CliEndToEnd, BadInputsFailWithAMessageNamingTheFile) {
  const Fixture& f = fixture();
  const std::filesystem::path d = f.dir;
  {
    std::ofstream bad(d / "bad.log");
    bad << "FLASER 3 1.0 2.0\n";  // too few fields
  }
  // A missing file is bad input (1), as CLI11's own check reported it with its own code before.
  EXPECT_EQ(run_cli("localize --map " + (d / "missing.yaml").string() + " --log " +
                        (d / "bad.log").string() + " --out " + (d / "x.tum").string(),
                    d / "bad1.txt"),
            1);
  EXPECT_TRUE(contains(read_all(d / "bad1.txt"),
                       "--map: File does not exist: " + (d / "missing.yaml").string()))
      << read_all(d / "bad1.txt");
  ASSERT_EQ(run_cli("map --log " + (d / "run.log").string() + " --resolution 0.1 --out " +
                        (d / "coarse").string() + " --quiet",
                    d / "coarse.txt"),
            0);
  EXPECT_EQ(
      run_cli("localize --map " + (d / "coarse.yaml").string() + " --log " +
                  (d / "bad.log").string() + " --method vdt-opt --out " + (d / "x.tum").string(),
              d / "bad2.txt"),
      1);
  EXPECT_TRUE(contains(read_all(d / "bad2.txt"), "bad.log:1: FLASER: expected"))
      << read_all(d / "bad2.txt");
  EXPECT_EQ(run_cli("localize --map " + (d / "coarse.yaml").string() + " --log " +
                        (d / "run.log").string() + " --method nope --out " + (d / "x.tum").string(),
                    d / "bad3.txt"),
            2);
  EXPECT_TRUE(contains(read_all(d / "bad3.txt"), "--method: nope not in"))
      << read_all(d / "bad3.txt");
}

TEST(CliEndToEnd, BadOptionsAreRefusedAndNothingIsWritten) {
  const Fixture& f = fixture();
  const std::filesystem::path d = f.dir / "options";
  std::filesystem::create_directories(d);
  const std::string log = (f.dir / "run.log").string();
  ASSERT_EQ(
      run_cli("map --log " + log + " --resolution 0.1 --out " + (d / "map").string() + " --quiet",
              d / "map.txt"),
      0)
      << read_all(d / "map.txt");
  const std::string localize = "localize --map " + (d / "map.yaml").string() + " --log " + log +
                               " --out " + (d / "x.tum").string() + " ";

  // A negative standard deviation (through the pose parser it was accepted).
  EXPECT_EQ(run_cli(localize + "--init-sigma 0.1,-0.1,0.05", d / "sigma.txt"), 2);
  EXPECT_TRUE(contains(read_all(d / "sigma.txt"),
                       "--init-sigma: expected three standard deviations sx,sy,syaw, finite and "
                       ">= 0 (metres, metres, radians), got '0.1,-0.1,0.05'"))
      << read_all(d / "sigma.txt");
  EXPECT_FALSE(std::filesystem::exists(d / "x.tum"));

  // An unknown time base.
  EXPECT_EQ(run_cli(localize + "--time-base gps", d / "time_base.txt"), 2);
  EXPECT_EQ(run_cli(localize + "--threads -1", d / "threads.txt"), 2);
  EXPECT_TRUE(contains(read_all(d / "time_base.txt"), "--time-base: gps not in {logger,ipc}"))
      << read_all(d / "time_base.txt");

  // A negative or non-finite margin.
  for (const char* margin : {"-1", "inf"}) {
    EXPECT_EQ(run_cli("map --log " + log + " --resolution 0.1 --margin " + margin + " --out " +
                          (d / "m").string() + " --quiet",
                      d / "margin.txt"),
              2)
        << margin;
    EXPECT_TRUE(
        contains(read_all(d / "margin.txt"),
                 std::string("--margin: expected a finite number of metres >= 0, got ") + margin))
        << read_all(d / "margin.txt");
    EXPECT_FALSE(std::filesystem::exists(d / "m.yaml")) << margin;
  }

  // A map with no occupied cell: refused before the YAML, PGM or VDT is written.
  write_no_return_log(d / "no_return.log", f.run.truth[0], 5);
  EXPECT_EQ(run_cli("map --log " + (d / "no_return.log").string() + " --resolution 0.1 --out " +
                        (d / "empty").string() + " --quiet",
                    d / "empty.txt"),
            1);
  EXPECT_TRUE(contains(
      read_all(d / "empty.txt"),
      (d / "no_return.log").string() + ": the map of 5 scans has no occupied cell (0 returns, " +
          std::to_string(5 * kBeams) + " no-returns at or beyond --max-range): nothing written"))
      << read_all(d / "empty.txt");
  for (const char* ext : {".yaml", ".pgm", ".vdt"}) {
    EXPECT_FALSE(std::filesystem::exists(d / (std::string("empty") + ext))) << ext;
  }
}

TEST(CliEndToEnd, IpcTimeBaseAndStrictOnAnUnexplainedLog) {
  const Fixture& f = fixture();
  const std::filesystem::path d = f.dir / "time_base";
  std::filesystem::create_directories(d);
  ASSERT_EQ(run_cli("map --log " + (f.dir / "run.log").string() + " --resolution 0.1 --out " +
                        (d / "map").string() + " --quiet",
                    d / "map.txt"),
            0)
      << read_all(d / "map.txt");
  // The run with ipc stamps 5000 s after the logger's.
  constexpr double kIpcOffset = 5000.0;
  CarmenLog log = load_carmen_log((f.dir / "run.log").string());
  for (CarmenLaser& l : log.lasers) l.ipc_time = l.time + kIpcOffset;
  save_carmen_log((d / "ipc.log").string(), log);
  const std::size_t first = 10;
  char from[64];
  std::snprintf(from, sizeof from, "%.6f", log.lasers[first].ipc_time - 1e-3);
  const std::string localize = "localize --map " + (d / "map.yaml").string() + " --log " +
                               (d / "ipc.log").string() + " --quiet --from " + from + " ";

  // The window and the trajectory in the ipc time base (and no --method: vdt-opt by default).
  ASSERT_EQ(run_cli(localize + "--time-base ipc --init " + std::to_string(f.run.truth[first][0]) +
                        "," + std::to_string(f.run.truth[first][1]) + "," +
                        std::to_string(f.run.truth[first][2]) + " --all-poses --out " +
                        (d / "ipc.tum").string(),
                    d / "ipc.txt"),
            0)
      << read_all(d / "ipc.txt");
  const TumTrajectory est = load_tum_trajectory((d / "ipc.tum").string());
  ASSERT_EQ(est.poses.size(), log.lasers.size() - first);
  for (std::size_t k = 0; k < est.poses.size(); ++k) {
    EXPECT_NEAR(est.poses[k].t, log.lasers[first + k].ipc_time, 1e-6);
  }
  EXPECT_TRUE(contains(read_all(d / "ipc.tum"), "# vdtnav localize --method vdt-opt"));
  EXPECT_FALSE(contains(read_all(d / "ipc.txt"), "warning"));
  // The same window in the logger time base holds no scan.
  EXPECT_EQ(run_cli(localize + "--out " + (d / "logger.tum").string(), d / "logger.txt"), 2);
  EXPECT_TRUE(contains(read_all(d / "logger.txt"), "no laser message in the time window"))
      << read_all(d / "logger.txt");

  // Scans the map never explains: the run completes (exit 3), its TUM file holds no pose and its
  // pose table one row per scan, none converged.
  write_no_return_log(d / "no_return.log", f.run.truth[0], 20);
  const std::string unexplained = "localize --map " + (d / "map.yaml").string() + " --log " +
                                  (d / "no_return.log").string() + " --quiet --out " +
                                  (d / "dr.tum").string() + " --cov " + (d / "dr.csv").string();
  EXPECT_EQ(run_cli(unexplained, d / "dr.txt"), 3) << read_all(d / "dr.txt");
  EXPECT_TRUE(contains(read_all(d / "dr.txt"), "vdtnav: only 0 of 20 scans (0.0 %) localized"))
      << read_all(d / "dr.txt");
  EXPECT_TRUE(load_tum_trajectory((d / "dr.tum").string()).poses.empty());
  std::ifstream table(d / "dr.csv");
  std::string row;
  std::getline(table, row);
  std::size_t rows = 0;
  while (std::getline(table, row)) {
    EXPECT_EQ(row.find(",converged,"), std::string::npos) << row;
    ++rows;
  }
  EXPECT_EQ(rows, 20u);
  // --all-poses writes them (dead reckoning, the table says so), and it is still exit 3.
  EXPECT_EQ(run_cli(unexplained + " --all-poses", d / "dr_all.txt"), 3);
  EXPECT_EQ(load_tum_trajectory((d / "dr.tum").string()).poses.size(), 20u);
}

TEST(CliEndToEnd, AFailedRunLeavesNothingOnDisk) {
  const Fixture& f = fixture();
  const std::filesystem::path d = f.dir / "atomic";
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d / "maps");
  ASSERT_EQ(run_cli("map --log " + (f.dir / "run.log").string() + " --resolution 0.1 --out " +
                        (d / "maps" / "map").string() + " --quiet",
                    d / "maps" / "map.txt"),
            0);
  // A log whose 30th line is broken: the run fails (exit 1) after the map is built and nothing is
  // left in the output folder, not even a temporary.
  {
    std::ifstream in(f.dir / "run.log");
    std::ofstream out(d / "broken.log");
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) out << (n == 30 ? "FLASER 3 1.0" : line) << "\n";
  }
  std::filesystem::create_directories(d / "out");
  EXPECT_EQ(run_cli("localize --map " + (d / "maps" / "map.yaml").string() + " --log " +
                        (d / "broken.log").string() + " --quiet --out " +
                        (d / "out" / "x.tum").string() + " --cov " +
                        (d / "out" / "x.csv").string() + " --plot " + (d / "out" / "x").string(),
                    d / "broken.txt"),
            1)
      << read_all(d / "broken.txt");
  EXPECT_TRUE(contains(read_all(d / "broken.txt"), "broken.log:30: "))
      << read_all(d / "broken.txt");
  EXPECT_TRUE(files_in(d / "out").empty());
  // An output folder that does not exist: bad input (1), before any work.
  EXPECT_EQ(run_cli("localize --map " + (d / "maps" / "map.yaml").string() + " --log " +
                        (f.dir / "run.log").string() + " --quiet --out " +
                        (d / "nowhere" / "x.tum").string(),
                    d / "nowhere.txt"),
            1);
  EXPECT_TRUE(contains(read_all(d / "nowhere.txt"), "does not exist"))
      << read_all(d / "nowhere.txt");
  // A run that completes writes all its outputs and no temporary.
  ASSERT_EQ(run_cli("localize --map " + (d / "maps" / "map.yaml").string() + " --log " +
                        (f.dir / "run.log").string() + " --quiet --out " +
                        (d / "out" / "x.tum").string() + " --cov " +
                        (d / "out" / "x.csv").string() + " --plot " + (d / "out" / "x").string(),
                    d / "ok.txt"),
            0)
      << read_all(d / "ok.txt");
  EXPECT_EQ(files_in(d / "out"),
            (std::vector<std::string>{"x.csv", "x.tum", "x_scans.png", "x_trajectory.png"}));
}

}  // namespace
}  // namespace vdtnav

namespace vdtnav {
namespace {

TEST(CliEndToEnd, SettingsFileIsPrintedReadBackAndChecked) {
  const Fixture& f = fixture();
  const std::filesystem::path d = f.dir / "settings";
  std::filesystem::create_directories(d);
  // --print-config needs no map or log; what it prints is a settings file that reads back to the
  // same settings.
  ASSERT_EQ(run_cli("localize --method vdt-opt --print-config", d / "printed.yaml"), 0)
      << read_all(d / "printed.yaml");
  const std::string printed = read_all(d / "printed.yaml");
  EXPECT_TRUE(contains(printed, "vdt-opt:"));
  EXPECT_FALSE(contains(printed, "vdt-ekf:"));
  EXPECT_TRUE(contains(printed, "loss: cauchy")) << "the log defaults";
  ASSERT_EQ(run_cli("localize --method vdt-opt --config " + (d / "printed.yaml").string() +
                        " --print-config",
                    d / "again.yaml"),
            0);
  EXPECT_EQ(read_all(d / "again.yaml"), printed);
  // A key the file names changes what is printed (and so what the localizer runs with).
  {
    std::ofstream(d / "mine.yaml") << "vdt-opt:\n  max_iterations: 7\n  search: {window_xy: 0.5}\n";
  }
  ASSERT_EQ(run_cli("localize --config " + (d / "mine.yaml").string() + " --print-config",
                    d / "mine.txt"),
            0);
  EXPECT_TRUE(contains(read_all(d / "mine.txt"), "max_iterations: 7 "));
  EXPECT_TRUE(contains(read_all(d / "mine.txt"), "window_xy: 0.5 "));
  // A typo is an error naming the file, the line and the key, before any map is built.
  { std::ofstream(d / "typo.yaml") << "vdt-opt:\n  search:\n    windw_xy: 0.5\n"; }
  EXPECT_EQ(run_cli("localize --map " + (d / "printed.yaml").string() + " --log " +
                        (f.dir / "run.log").string() + " --out " + (d / "x.tum").string() +
                        " --config " + (d / "typo.yaml").string(),
                    d / "typo.txt"),
            1);
  EXPECT_TRUE(
      contains(read_all(d / "typo.txt"), "typo.yaml:3: vdt-opt.search.windw_xy: unknown key"))
      << read_all(d / "typo.txt");
  // Without --print-config the map, log and output are required.
  EXPECT_EQ(run_cli("localize --method vdt-ekf", d / "required.txt"), 2);
  EXPECT_TRUE(contains(read_all(d / "required.txt"), "localize: --map is required"))
      << read_all(d / "required.txt");
}

}  // namespace
}  // namespace vdtnav
