// The UAV downward camera's front end (thesis 3.4.3): edge extraction on a 640x480 frame of
// runway-like paint, and the projection of 2000 edge pixels to the ground (undistortion included).
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "../bench_counters.hpp"
#include "vdtnav/uav_camera/edge_extraction.hpp"
#include "vdtnav/uav_camera/ground_projection.hpp"

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

}  // namespace
}  // namespace vdtnav::uav_camera
