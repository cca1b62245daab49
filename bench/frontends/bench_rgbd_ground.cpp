// The RGB-D ground-boundary front end (thesis 3.4.5): one 640 x 480 frame's boundaries (plane
// fit, chroma edges, pruning, back-projection with covariances) on the real Kinect frames of
// ../shared/data (skipped with a message without them), and one VDT EKF update with 1000 such
// points (a full 2 x 2 covariance each) on the generated floor plan.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "../bench_counters.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/rgbd_ground/camera_mount.hpp"
#include "vdtnav/rgbd_ground/ground_boundaries.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav {
namespace {

void BM_RgbdBoundaries(benchmark::State& state) {
  const std::string dir = std::string(VDTNAV_DATA_DIR) + "/vision/rgbd-kinect";
  if (!std::filesystem::exists(dir + "/depth/1.pgm")) {
    state.SkipWithError(("real data absent: " + dir).c_str());
    return;
  }
  camera::CameraCalibration cal;
  cal.width = 640;
  cal.height = 480;
  cal.camera_matrix << 518.0, 0.0, 325.5, 0.0, 519.0, 253.5, 0.0, 0.0, 1.0;
  // A hand-held camera ~1.4 m up, looking forward and ~25 degrees down (as the tests).
  const Eigen::Isometry3d nominal =
      rgbd_ground::tilted_camera(Eigen::Vector3d(0.0, 0.0, 1.4), 0.0, 25.0 * M_PI / 180.0);
  rgbd_ground::GroundBoundaryOptions o;
  o.plane.max_tilt = 0.6;
  const rgbd_ground::GroundBoundaryExtractor ex(camera::PinholeCamera(cal), nominal, o);
  std::vector<rgbd_ground::RgbdFrame> frames;
  for (int i = 1; i <= 5; ++i) {
    frames.push_back(rgbd_ground::read_rgbd_frame(dir + "/color/" + std::to_string(i) + ".png",
                                                  dir + "/depth/" + std::to_string(i) + ".pgm",
                                                  1000.0));
  }
  std::size_t k = 0;
  double points = 0.0;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    const rgbd_ground::GroundBoundaries b = ex.extract(frames[k]);
    benchmark::DoNotOptimize(b);
    points += static_cast<double>(b.points.size());
    k = (k + 1) % frames.size();
  }
  timer.set(state, "ms_per_frame", 1.0, 1e-6);
  state.counters["points"] = points / static_cast<double>(state.iterations());
}
BENCHMARK(BM_RgbdBoundaries)->Name("BM_RgbdBoundaries/640x480")->Unit(benchmark::kMillisecond);

void BM_RgbdEkfUpdate(benchmark::State& state) {
  const sim::FloorPlan plan = sim::generate_floor_plan({});
  const VdtMap2 map = VdtMap2::build(plan.occupancy);
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  // Ground points from the walls around a pose of the tour (a camera sees boundaries within a
  // few metres), each with the anisotropic covariance of a back-projected pixel.
  const Eigen::Vector2d a = plan.tour[2], b = plan.tour[3];
  const Pose2 truth(0.5 * (a.x() + b.x()), 0.5 * (a.y() + b.y()),
                    std::atan2(b.y() - a.y(), b.x() - a.x()));
  std::mt19937 rng(3);
  std::normal_distribution<double> n01(0.0, 1.0);
  ScanPoints pts;
  for (std::size_t i = 0; pts.size() < n && i < 20 * n; ++i) {
    const double ang = -M_PI + 2.0 * M_PI * static_cast<double>(i % n) / static_cast<double>(n);
    const double rr =
        sim::cast_ray<2>(plan.occupancy, truth.head<2>(),
                         Eigen::Vector2d(std::cos(truth[2] + ang), std::sin(truth[2] + ang)), 8.0,
                         sim::RaySurface::kCellCentre);
    if (!std::isfinite(rr)) continue;
    const Eigen::Vector2d u(std::cos(ang), std::sin(ang));
    Eigen::Matrix2d cov = 1e-4 * Eigen::Matrix2d::Identity() + 4e-4 * u * u.transpose();
    pts.add_point((rr + 0.02 * n01(rng)) * u, cov, i);
  }
  VdtEkfOptions eo;
  eo.motion = MotionModelKind::kOdometryIncrement;
  VdtEkfLocalizer ekf(map, eo);
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    ekf.reset(truth + Pose2(0.03, -0.02, 0.01), Eigen::Vector3d(4e-4, 4e-4, 1e-4).asDiagonal());
    const LocalizationResult r = ekf.update(OdometryStep{}, pts);
    benchmark::DoNotOptimize(r);
  }
  timer.set(state, "ms_per_update", 1.0, 1e-6);
  state.counters["points"] = static_cast<double>(pts.size());
}
BENCHMARK(BM_RgbdEkfUpdate)->Arg(1000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vdtnav
