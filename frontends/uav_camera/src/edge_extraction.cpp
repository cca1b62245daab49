#include "vdtnav/uav_camera/edge_extraction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include <opencv2/imgproc.hpp>

#include "vdtnav/core/error.hpp"

namespace vdtnav::uav_camera {
namespace {

cv::Mat to_gray(const cv::Mat& image) {
  VDTNAV_CHECK(!image.empty(), "extract_edges: the image is empty");
  VDTNAV_CHECK(image.depth() == CV_8U &&
                   (image.channels() == 1 || image.channels() == 3 || image.channels() == 4),
               "extract_edges: expected an 8-bit gray, BGR or BGRA image, got type " +
                   std::to_string(image.type()));
  if (image.channels() == 1) return image;
  cv::Mat gray;
  cv::cvtColor(image, gray, image.channels() == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
  return gray;
}

/// Median of non-negative values given by `value(row, col)`, to 1/bins_per_unit, by histogram.
template <typename F>
double histogram_median(int rows, int cols, int border, double max_value, double bins_per_unit,
                        F value) {
  const int nbins = static_cast<int>(max_value * bins_per_unit) + 2;
  std::vector<std::uint32_t> hist(static_cast<std::size_t>(nbins), 0);
  std::size_t n = 0;
  for (int r = border; r < rows - border; ++r) {
    for (int c = border; c < cols - border; ++c) {
      const int b = std::min(nbins - 1, static_cast<int>(value(r, c) * bins_per_unit));
      ++hist[static_cast<std::size_t>(b)];
      ++n;
    }
  }
  if (n == 0) return 0.0;
  std::size_t acc = 0;
  for (int b = 0; b < nbins; ++b) {
    acc += hist[static_cast<std::size_t>(b)];
    if (2 * acc >= n) return (b + 0.5) / bins_per_unit;
  }
  return max_value;
}

/// |k1 * k2| (full 1D convolution), squared.
double conv_norm2(const cv::Mat& g, const double* k, int nk) {
  const int ng = g.rows * g.cols;
  double s = 0.0;
  for (int i = 0; i < ng + nk - 1; ++i) {
    double v = 0.0;
    for (int j = 0; j < nk; ++j) {
      const int gi = i - j;
      if (gi >= 0 && gi < ng) v += g.at<double>(gi) * k[j];
    }
    s += v * v;
  }
  return s;
}

}  // namespace

cv::Mat edge_image(const cv::Mat& image, const EdgeOptions& options, EdgeThresholds* thresholds) {
  VDTNAV_CHECK(std::isfinite(options.blur_sigma) && options.blur_sigma >= 0.0,
               "EdgeOptions: blur_sigma must be >= 0");
  VDTNAV_CHECK(options.high_factor > 0.0 && options.low_factor > 0.0 &&
                   options.low_factor <= options.high_factor && options.noise_factor >= 0.0,
               "EdgeOptions: expected 0 < low_factor <= high_factor and noise_factor >= 0");
  VDTNAV_CHECK(options.border >= 0, "EdgeOptions: border must be >= 0");
  const cv::Mat gray = to_gray(image);
  const int rows = gray.rows;
  const int cols = gray.cols;
  const int stat_border = std::min(std::max(options.border, 1), std::min(rows, cols) / 2);

  // Image noise: median |high-pass| / (0.6745 |N|), |N| = 6 (MAD of a Gaussian).
  cv::Mat hp;
  const cv::Mat n_kernel = (cv::Mat_<float>(3, 3) << 1, -2, 1, -2, 4, -2, 1, -2, 1);
  cv::filter2D(gray, hp, CV_16S, n_kernel, cv::Point(-1, -1), 0.0, cv::BORDER_REPLICATE);
  const double hp_median = histogram_median(
      rows, cols, stat_border, 16.0 * 255.0, 1.0,
      [&](int r, int c) { return std::abs(static_cast<double>(hp.at<std::int16_t>(r, c))); });
  const double sigma_n = hp_median / (0.6745 * 6.0);

  cv::Mat blurred;  // a fresh buffer: `gray` may share the caller's image
  cv::Mat g_kernel = (cv::Mat_<double>(1, 1) << 1.0);
  if (options.blur_sigma > 0.0) {
    // OpenCV's automatic size for 8-bit images, so the kernel below is the one applied.
    const int ksize = (static_cast<int>(std::lround(options.blur_sigma * 6.0 + 1.0))) | 1;
    g_kernel = cv::getGaussianKernel(ksize, options.blur_sigma, CV_64F);
    cv::GaussianBlur(gray, blurred, cv::Size(ksize, ksize), options.blur_sigma, options.blur_sigma,
                     cv::BORDER_REPLICATE);
  } else {
    blurred = gray;
  }
  // Noise of one Sobel component: sigma_n |G * [1 2 1]| |G * [-1 0 1]|, plus the rounding of the
  // blurred image to 8 bits (variance 1/12 through the Sobel kernel, |S|^2 = 12).
  const double smooth[3] = {1.0, 2.0, 1.0};
  const double deriv[3] = {-1.0, 0.0, 1.0};
  const double sigma_g = std::sqrt(
      sigma_n * sigma_n * conv_norm2(g_kernel, smooth, 3) * conv_norm2(g_kernel, deriv, 3) + 1.0);

  cv::Mat dx;
  cv::Mat dy;
  cv::Sobel(blurred, dx, CV_16S, 1, 0, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
  cv::Sobel(blurred, dy, CV_16S, 0, 1, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
  const double g_median = histogram_median(rows, cols, stat_border, 1500.0, 4.0, [&](int r, int c) {
    const double gx = dx.at<std::int16_t>(r, c);
    const double gy = dy.at<std::int16_t>(r, c);
    return std::sqrt(gx * gx + gy * gy);
  });

  const double high = std::max(options.high_factor * g_median, options.noise_factor * sigma_g);
  const double low = std::max(options.low_factor * g_median, 0.5 * options.noise_factor * sigma_g);
  cv::Mat edges;
  cv::Canny(dx, dy, edges, low, high, /*L2gradient=*/true);
  const int b = std::min(options.border, std::min(rows, cols));
  if (b > 0) {
    edges.rowRange(0, b).setTo(0);
    edges.rowRange(rows - b, rows).setTo(0);
    edges.colRange(0, b).setTo(0);
    edges.colRange(cols - b, cols).setTo(0);
  }
  if (options.min_chain > 1) {
    // Short chains are texture (asphalt grain, grass, gravel), not the boundary of a marking:
    // drop 8-connected edge chains of fewer than min_chain pixels.
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(edges, labels, stats, centroids, 8, CV_32S);
    std::vector<char> keep(static_cast<std::size_t>(n), 0);
    for (int k = 1; k < n; ++k) keep[k] = stats.at<int>(k, cv::CC_STAT_AREA) >= options.min_chain;
    for (int r = 0; r < rows; ++r) {
      const int* lr = labels.ptr<int>(r);
      std::uint8_t* er = edges.ptr<std::uint8_t>(r);
      for (int c = 0; c < cols; ++c) {
        if (er[c] != 0 && !keep[lr[c]]) er[c] = 0;
      }
    }
  }
  if (thresholds != nullptr) *thresholds = {low, high, sigma_n, g_median};
  return edges;
}

std::vector<Eigen::Vector2d> extract_edges(const cv::Mat& image, const EdgeOptions& options) {
  const cv::Mat edges = edge_image(image, options);
  const int rows = edges.rows;
  const int cols = edges.cols;
  std::vector<Eigen::Vector2d> all;
  for (int r = 0; r < rows; ++r) {
    const std::uint8_t* row = edges.ptr<std::uint8_t>(r);
    for (int c = 0; c < cols; ++c) {
      if (row[c] != 0) all.emplace_back(c, r);
    }
  }
  const std::size_t budget = options.max_points;
  if (budget == 0 || all.size() <= budget) return all;

  // Spatially uniform subsample: cells of about area / budget pixels each; each round takes the
  // next point of every cell that still has one, so sparse regions keep all their points and
  // dense ones give up theirs evenly. Within a cell the points are visited in a fixed
  // pseudo-random order (our own LCG: identical on every platform).
  const double area = static_cast<double>(rows) * cols;
  const int cell = std::max(2, static_cast<int>(std::lround(std::sqrt(area / budget))));
  const int ncx = (cols + cell - 1) / cell;
  const int ncy = (rows + cell - 1) / cell;
  std::vector<std::vector<std::uint32_t>> cells(static_cast<std::size_t>(ncx) * ncy);
  for (std::size_t i = 0; i < all.size(); ++i) {
    const int cx = static_cast<int>(all[i].x()) / cell;
    const int cy = static_cast<int>(all[i].y()) / cell;
    cells[static_cast<std::size_t>(cy) * ncx + cx].push_back(static_cast<std::uint32_t>(i));
  }
  std::uint64_t state = 0x9E3779B97F4A7C15ULL;
  for (auto& c : cells) {
    for (std::size_t i = c.size(); i > 1; --i) {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      const std::size_t j = static_cast<std::size_t>((state >> 33) % i);
      std::swap(c[i - 1], c[j]);
    }
  }
  std::vector<Eigen::Vector2d> out;
  out.reserve(budget);
  std::vector<std::size_t> round_cells;
  for (std::size_t round = 0; out.size() < budget; ++round) {
    round_cells.clear();
    for (std::size_t k = 0; k < cells.size(); ++k) {
      if (cells[k].size() > round) round_cells.push_back(k);
    }
    const std::size_t need = budget - out.size();
    if (round_cells.size() <= need) {
      for (std::size_t k : round_cells) out.push_back(all[cells[k][round]]);
    } else {
      // Last, partial round: cells evenly spaced over the list, not the first ones.
      for (std::size_t t = 0; t < need; ++t) {
        const std::size_t k = round_cells[t * round_cells.size() / need];
        out.push_back(all[cells[k][round]]);
      }
    }
  }
  return out;
}

}  // namespace vdtnav::uav_camera
