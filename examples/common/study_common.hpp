#pragma once
// What the studies share (examples/*): the statistics their tables print, and camera frames as
// figures' images. One place, so that two studies cannot compute a table's column two ways.

#include <cmath>
#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "vdtnav/viz/image.hpp"

namespace vdtnav::study {

/// \return sqrt(mean of squares) of `v`; NaN when empty.
inline double rms(const std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s / static_cast<double>(v.size()));
}

/// \return a camera frame as an image for a figure: 8-bit grey (CV_8UC1) or BGR (CV_8UC3).
inline viz::RgbImage to_rgb(const cv::Mat& frame) {
  viz::RgbImage img(frame.cols, frame.rows);
  for (int r = 0; r < frame.rows; ++r) {
    for (int c = 0; c < frame.cols; ++c) {
      std::uint8_t* px = &img.rgb[3 * (static_cast<std::size_t>(r) * frame.cols + c)];
      if (frame.channels() == 1) {
        px[0] = px[1] = px[2] = frame.at<std::uint8_t>(r, c);
      } else {
        const cv::Vec3b v = frame.at<cv::Vec3b>(r, c);
        px[0] = v[2];
        px[1] = v[1];
        px[2] = v[0];
      }
    }
  }
  return img;
}

}  // namespace vdtnav::study
