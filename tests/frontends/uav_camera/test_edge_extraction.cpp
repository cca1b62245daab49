// Edge pixels: on the true boundary of a rendered marking, within the budget, spread over all of
// it; nothing on plain noisy ground.
#include "vdtnav/uav_camera/edge_extraction.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "vdtnav/core/error.hpp"

namespace vdtnav::uav_camera {
namespace {

// The white rectangle covers pixels u in [kU0, kU1], v in [kV0, kV1]: its boundary lies half a
// pixel outside (u = kU0 - 0.5, ...).
constexpr int kU0 = 150, kU1 = 449, kV0 = 100, kV1 = 349;

cv::Mat rectangle_image(double noise_sigma, unsigned seed = 1) {
  cv::Mat img(480, 640, CV_32F, cv::Scalar(100.0));
  img(cv::Range(kV0, kV1 + 1), cv::Range(kU0, kU1 + 1)).setTo(220.0);
  cv::GaussianBlur(img, img, cv::Size(0, 0), 1.0);
  cv::Mat noise(img.size(), CV_32F);
  cv::theRNG().state = seed;
  cv::randn(noise, 0.0, noise_sigma);
  img += noise;
  cv::Mat out;
  img.convertTo(out, CV_8U);
  return out;
}

/// Distance from pixel centre p to the rectangle's boundary.
double distance_to_boundary(const Eigen::Vector2d& p) {
  const double l = kU0 - 0.5, r = kU1 + 0.5, t = kV0 - 0.5, b = kV1 + 0.5;
  const double dx = std::max({l - p.x(), 0.0, p.x() - r});
  const double dy = std::max({t - p.y(), 0.0, p.y() - b});
  if (dx > 0 || dy > 0) return std::hypot(dx, dy);
  return std::min({p.x() - l, r - p.x(), p.y() - t, b - p.y()});  // inside
}

TEST(ExtractEdges, RectangleEdgesLieOnItsBoundaryAndCoverEverySide) {
  const cv::Mat img = rectangle_image(2.0);
  EdgeOptions options;
  options.max_points = 200;
  const auto edges = extract_edges(img, options);
  ASSERT_EQ(edges.size(), 200U);  // the full edge set is ~1100 pixels: the budget is used
  for (const auto& p : edges) {
    EXPECT_LE(distance_to_boundary(p), 1.0) << p.transpose();
    EXPECT_EQ(p.x(), std::round(p.x()));
  }
  // Each side gets points spread along all of it (largest gap well under a side's length).
  std::vector<double> sides[4];
  for (const auto& p : edges) {
    if (std::abs(p.x() - (kU0 - 0.5)) <= 1.0) sides[0].push_back(p.y());
    if (std::abs(p.x() - (kU1 + 0.5)) <= 1.0) sides[1].push_back(p.y());
    if (std::abs(p.y() - (kV0 - 0.5)) <= 1.0) sides[2].push_back(p.x());
    if (std::abs(p.y() - (kV1 + 0.5)) <= 1.0) sides[3].push_back(p.x());
  }
  const double lo[4] = {kV0, kV0, kU0, kU0};
  const double hi[4] = {kV1, kV1, kU1, kU1};
  for (int s = 0; s < 4; ++s) {
    ASSERT_GE(sides[s].size(), 25U) << "side " << s;
    auto v = sides[s];
    v.push_back(lo[s]);
    v.push_back(hi[s]);
    std::sort(v.begin(), v.end());
    double gap = 0.0;
    for (std::size_t i = 1; i < v.size(); ++i) gap = std::max(gap, v[i] - v[i - 1]);
    EXPECT_LT(gap, 45.0) << "side " << s;
  }
  // Without a budget, the whole outline (~1100 pixels), and a BGR copy gives the same result.
  options.max_points = 0;
  const auto all = extract_edges(img, options);
  EXPECT_GT(all.size(), 1000U);
  EXPECT_LT(all.size(), 1300U);
  cv::Mat bgr;
  cv::cvtColor(img, bgr, cv::COLOR_GRAY2BGR);
  EXPECT_EQ(extract_edges(bgr, options), all);
}

TEST(ExtractEdges, IsDeterministic) {
  const cv::Mat img = rectangle_image(3.0);
  EdgeOptions options;
  options.max_points = 300;
  const cv::Mat copy = img.clone();
  EXPECT_EQ(extract_edges(img, options), extract_edges(img, options));
  EXPECT_EQ(cv::norm(img, copy, cv::NORM_INF), 0.0);  // the input is left alone
}

TEST(ExtractEdges, PlainNoisyGroundHasFewEdges) {
  cv::Mat img(480, 640, CV_8U);
  cv::theRNG().state = 3;
  cv::randn(img, 120.0, 3.0);
  EdgeThresholds t;
  (void)edge_image(img, {}, &t);
  EXPECT_NEAR(t.noise_sigma, 3.0, 0.5);  // the robust noise estimate
  EXPECT_LT(extract_edges(img, {}).size(), 50U);
  // ...while the same noise on the marking still gives its outline.
  EXPECT_GT(extract_edges(rectangle_image(3.0), EdgeOptions{1.2, 3.0, 1.5, 6.0, 0, 3}).size(),
            1000U);
}

TEST(ExtractEdges, BorderIsIgnored) {
  // A step at the very top of the image: it lies inside the ignored border.
  cv::Mat img(100, 100, CV_8U, cv::Scalar(50));
  img.rowRange(0, 2).setTo(250);
  for (const auto& p : extract_edges(img, {})) {
    EXPECT_GE(p.y(), 3.0);
  }
}

TEST(ExtractEdges, RejectsEmptyAndUnsupportedImages) {
  EXPECT_THROW((void)extract_edges(cv::Mat(), {}), ConfigError);
  EXPECT_THROW((void)extract_edges(cv::Mat(10, 10, CV_32F, cv::Scalar(0)), {}), ConfigError);
  EXPECT_THROW((void)extract_edges(cv::Mat(10, 10, CV_8UC2, cv::Scalar(0)), {}), ConfigError);
}

}  // namespace
}  // namespace vdtnav::uav_camera
