// The UAV downward camera's front end (thesis 3.4.3): edge extraction on a 640x480 frame of
// runway-like paint, the projection of 2000 edge pixels to the ground (undistortion included),
// and a whole localization step on a rendered runway frame (edges + projection + VDT solve).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "../bench_counters.hpp"
#include "vdtnav/camera_sim/ground_renderer.hpp"
#include "vdtnav/camera_sim/runway_scene.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/uav_camera/edge_extraction.hpp"
#include "vdtnav/uav_camera/ground_projection.hpp"
#include "vdtnav/uav_camera/marking_map.hpp"
#include "vdtnav/uav_camera/uav_camera_front_end.hpp"

namespace vdtnav::uav_camera {
namespace {

/// White stripes and a threshold-bar pattern on noisy grey tarmac, blurred like a real lens.
cv::Mat runway_frame(int width, int height) {
  cv::Mat img(height, width, CV_32F, cv::Scalar(90.0));
  const cv::Scalar white(230.0);
  cv::line(img, {width / 2, 0}, {width / 2 + width / 10, height - 1}, white, 9);  // centre line
  for (int k = 0; k < 6; ++k) {                                                   // threshold bars
    const int x = width / 10 + k * width / 8;
    cv::rectangle(img, {x, height / 8}, {x + width / 20, height / 3}, white, cv::FILLED);
  }
  cv::rectangle(img, {width / 8, height * 2 / 3}, {width * 3 / 8, height * 5 / 6}, white,
                cv::FILLED);  // a touchdown block
  cv::GaussianBlur(img, img, cv::Size(0, 0), 1.5);
  cv::Mat noise(img.size(), CV_32F);
  cv::theRNG().state = 1;
  cv::randn(noise, 0.0, 4.0);
  img += noise;
  cv::Mat out;
  img.convertTo(out, CV_8U);
  return out;
}

void BM_UavEdges(benchmark::State& state) {
  const cv::Mat frame = runway_frame(640, 480);
  std::size_t n = 0;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    const auto edges = extract_edges(frame, {});
    n = edges.size();
    benchmark::DoNotOptimize(edges.data());
  }
  timer.set(state, "ms_per_frame", 1.0, 1e-6);
  state.counters["edge_pixels"] = static_cast<double>(n);
}
BENCHMARK(BM_UavEdges)->Name("BM_UavEdges/640x480")->Unit(benchmark::kMillisecond);

void BM_UavGroundProjection(benchmark::State& state) {
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  c.camera_matrix << 400.0, 0.0, 321.3, 0.0, 401.5, 238.7, 0.0, 0.0, 1.0;
  c.distortion = {-0.28, 0.09, 0.0012, -0.0007, -0.012};
  const PinholeCamera camera(c);
  const std::size_t n = 2000;
  std::vector<Eigen::Vector2d> pixels;
  pixels.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {  // scattered over the whole image (golden-ratio lattice)
    const double t = static_cast<double>(i) + 0.5;
    pixels.emplace_back(std::fmod(t * 0.6180339887498949, 1.0) * 639.0, t / n * 479.0);
  }
  const UavRig rig;
  const AttitudeReading attitude{0.05, -0.03, 30.0};
  std::size_t kept = 0;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    const ObservationSet2 obs = ground_observations(pixels, camera, rig, attitude);
    kept = obs.size();
    benchmark::DoNotOptimize(obs.points.data());
  }
  timer.set(state, "ns_per_point", static_cast<double>(n));
  state.counters["kept"] = static_cast<double>(kept);
}
BENCHMARK(BM_UavGroundProjection)->Name("BM_UavGroundProjection/2000");

void BM_UavLocalize(benchmark::State& state) {
  // Prepared once: the runway scene of the example (narrow grass margin), its marking map, and a
  // frame rendered over the road at 15 m with a few degrees of roll and pitch.
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  RunwaySceneOptions so;
  so.grass_margin = 2.0;
  const RunwayScene scene = make_runway_scene(so);
  const VdtMap2 map = VdtMap2::build(marking_boundaries(scene.markings));
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  const double f = 0.5 * c.width / std::tan(30.0 * kDeg);  // 60 degree field of view
  c.camera_matrix << f, 0.0, 319.5, 0.0, f, 239.5, 0.0, 0.0, 1.0;
  c.distortion = {-0.12, 0.03, 0.0005, -0.0003, 0.0};
  const UavRig rig;
  const std::size_t i = 100;  // 10 m from the crossing, on the straight leg
  const Eigen::Vector2d dir = scene.centreline[i + 1] - scene.centreline[i - 1];
  const Pose2 truth(scene.centreline[i].x(), scene.centreline[i].y(), std::atan2(dir.y(), dir.x()));
  const double h = 15.0, roll = 3.0 * kDeg, pitch = -2.0 * kDeg;
  std::mt19937_64 rng(1);
  const cv::Mat image = GroundRenderer(c, rig).render(
      scene.texture, body_pose(truth[0], truth[1], h, roll, pitch, truth[2]), {}, rng);
  UavCameraOptions co;
  co.edges.max_points = static_cast<std::size_t>(state.range(0));
  const UavCameraFrontEnd front(c, rig, co);
  const AttitudeReading reading{roll, pitch, h / (std::cos(roll) * std::cos(pitch))};
  VdtOptimizerOptions oo;  // the example's settings
  oo.sensor.gate = 10.0 * map.resolution();
  oo.min_inliers = 50;
  const VdtOptimizer optimizer(map, oo);
  const Pose2 guess = truth + Pose2(0.03, -0.02, 0.01);  // tracking: a few cm, 0.01 rad off
  std::size_t points = 0;
  double error = 0.0;
  bool converged = false;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    const CameraFrame frame = front.observe(image, reading);
    const LocalizationResult r = optimizer.solve(frame.observations, guess);
    points = frame.observations.size();
    error = 1e3 * (r.pose - truth).head<2>().norm();
    converged = r.status == LocalizationStatus::kConverged;
    benchmark::DoNotOptimize(r.covariance.data());
  }
  timer.set(state, "ms_per_frame", 1.0, 1e-6);
  state.counters["points"] = static_cast<double>(points);
  state.counters["error_mm"] = error;
  state.counters["converged"] = converged ? 1.0 : 0.0;
}
BENCHMARK(BM_UavLocalize)->Arg(2000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vdtnav::uav_camera
