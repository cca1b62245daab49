#pragma once
/// \file
/// \brief Edge pixels of a camera image (thesis 3.4.3: the edges of ground markings), with
/// thresholds derived from the image itself and a spatially uniform subsample.

#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

namespace vdtnav::uav_camera {

/// \brief Settings of extract_edges().
///
/// Threshold rule. Canny's hysteresis thresholds act on the L2 magnitude of the 3x3 Sobel
/// gradient of the blurred image. They are
///   high = max(high_factor * g_median, noise_factor * sigma_g),
///   low  = max(low_factor * g_median, 0.5 * noise_factor * sigma_g),
/// with g_median the median gradient magnitude over the image (it follows the contrast of the
/// texture, so busy frames need stronger edges than calm ones) and sigma_g the standard deviation
/// of one gradient component that the image noise alone produces: sigma_g^2 =
/// sigma_n^2 |S * G|^2 + 1 (the second term: rounding the blurred image to 8 bits), sigma_n the
/// noise estimated robustly from the raw image (median absolute response of the 3x3 Laplacian-
/// like high-pass [1 -2 1; -2 4 -2; 1 -2 1], which lines and straight edges barely excite) and
/// |S * G| the norm of the Sobel-of-Gaussian kernel. Noise alone exceeds 6 sigma_g with
/// probability exp(-18) ~ 1.5e-8 (Rayleigh; 5 sigma_g still let ~10 noise pixels per 640 x 480
/// frame through), so a nearly uniform image (grass, tarmac) does not
/// light up with texture edges, which a rule on the gradient statistic alone would let happen.
struct EdgeOptions {
  double blur_sigma = 1.2;        ///< Gaussian blur before the gradient, pixels (0: none)
  double high_factor = 3.0;       ///< Canny high threshold, times the median gradient magnitude
  double low_factor = 1.5;        ///< Canny low threshold, times the median gradient magnitude
  double noise_factor = 6.0;      ///< high threshold >= this times the noise gradient sigma_g
  std::size_t max_points = 2000;  ///< most edge pixels returned (0: all)
  int border = 3;                 ///< pixels ignored along the image border
  /// Edge chains (8-connected) shorter than this many pixels are dropped: the boundary of a
  /// marking or a field is a long chain, the grain of asphalt or grass makes short ones. 1: keep
  /// all. The default, 30 px, is 0.8 m on the ground at 15 m with a 60 degree, 640 px camera.
  int min_chain = 30;
};

/// \brief The thresholds the rule above gives for one image (for diagnostics and tests).
struct EdgeThresholds {
  double low = 0.0;
  double high = 0.0;
  double noise_sigma = 0.0;  ///< estimated image noise, grey levels
  double median_gradient = 0.0;
};

/// \brief Canny edge map (CV_8U, 255 on edges, the border cleared) with the thresholds of
/// EdgeOptions. \throws ConfigError for an empty image or one that is not 8-bit gray or BGR(A).
[[nodiscard]] cv::Mat edge_image(const cv::Mat& image, const EdgeOptions& options = {},
                                 EdgeThresholds* thresholds = nullptr);

/// \brief Edge pixels (u = column, v = row; integer coordinates are pixel centres) of an 8-bit
/// gray or BGR image, at most options.max_points of them, spread uniformly over the image: a grid
/// of cells takes one point per cell in turn until the budget is used (deterministic).
/// \throws ConfigError for an empty image or one that is not 8-bit gray or BGR(A).
[[nodiscard]] std::vector<Eigen::Vector2d> extract_edges(const cv::Mat& image,
                                                         const EdgeOptions& options = {});

}  // namespace vdtnav::uav_camera
