#include "vdtnav/camera_sim/ground_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/pose3.hpp"

namespace vdtnav::uav_camera {
namespace {

// Bilinear grey level of a CV_8UC1 / CV_8UC3 texture at continuous pixel coordinates (cu, cv),
// pixel centres at integers; `background` off the image.
template <int Channels>
inline float bilinear(const cv::Mat& image, float cu, float cv, float background) {
  const int cols = image.cols, rows = image.rows;
  if (!(cu >= -0.5f && cv >= -0.5f && cu < cols - 0.5f && cv < rows - 0.5f)) return background;
  const float fu_floor = std::floor(cu), fv_floor = std::floor(cv);
  const float fu = cu - fu_floor, fv = cv - fv_floor;
  const int c0 = std::max(static_cast<int>(fu_floor), 0);
  const int r0 = std::max(static_cast<int>(fv_floor), 0);
  const int c1 = std::min(static_cast<int>(fu_floor) + 1, cols - 1);
  const int r1 = std::min(static_cast<int>(fv_floor) + 1, rows - 1);
  const std::uint8_t* row0 = image.ptr<std::uint8_t>(r0);
  const std::uint8_t* row1 = image.ptr<std::uint8_t>(r1);
  const auto grey = [](const std::uint8_t* row, int c) -> float {
    if constexpr (Channels == 1) {
      return row[c];
    } else {
      const std::uint8_t* p = row + 3 * c;
      return 0.114f * p[0] + 0.587f * p[1] + 0.299f * p[2];  // BT.601 luma of BGR
    }
  };
  const float top = grey(row0, c0) + fu * (grey(row0, c1) - grey(row0, c0));
  const float bottom = grey(row1, c0) + fu * (grey(row1, c1) - grey(row1, c0));
  return top + fv * (bottom - top);
}

// Normalised kernel of a linear motion of `length` pixels along `angle`: the segment sampled
// densely and splatted bilinearly, so that fractional lengths and any direction are exact.
cv::Mat motion_blur_kernel(double length, double angle) {
  const int half = static_cast<int>(std::ceil(0.5 * length)) + 1;
  cv::Mat kernel = cv::Mat::zeros(2 * half + 1, 2 * half + 1, CV_32F);
  const int samples = 16 * static_cast<int>(std::ceil(length)) + 1;
  const double dx = std::cos(angle), dy = std::sin(angle);
  for (int k = 0; k < samples; ++k) {
    const double s = length * (static_cast<double>(k) / (samples - 1) - 0.5);
    const double x = half + s * dx, y = half + s * dy;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    kernel.at<float>(y0, x0) += static_cast<float>((1 - fx) * (1 - fy));
    kernel.at<float>(y0, x0 + 1) += static_cast<float>(fx * (1 - fy));
    kernel.at<float>(y0 + 1, x0) += static_cast<float>((1 - fx) * fy);
    kernel.at<float>(y0 + 1, x0 + 1) += static_cast<float>(fx * fy);
  }
  kernel /= cv::sum(kernel)[0];
  return kernel;
}

}  // namespace

Eigen::Isometry3d body_pose(double x, double y, double altitude, double roll, double pitch,
                            double yaw) {
  return pose3_from_xyz_rpy(x, y, altitude, roll, pitch, yaw);  // R = Rz Ry Rx, as uav_rig.hpp
}

GroundRenderer::GroundRenderer(const CameraCalibration& calibration, const UavRig& rig)
    : calibration_(calibration), rig_(rig) {
  const Eigen::Matrix3d& k = calibration.camera_matrix;
  VDTNAV_CHECK(calibration.width > 0 && calibration.height > 0,
               "GroundRenderer: image width and height must be > 0");
  VDTNAV_CHECK(k(0, 0) > 0.0 && k(1, 1) > 0.0 && k.allFinite(),
               "GroundRenderer: fx and fy must be finite and > 0");
  const std::size_t n = calibration.distortion.size();
  VDTNAV_CHECK(n == 0 || n == 4 || n == 5 || n == 8 || n == 12 || n == 14,
               "GroundRenderer: distortion must have 0, 4, 5, 8, 12 or 14 coefficients");
  const int w = calibration.width, h = calibration.height;

  // Undistorted normalized rays of every pixel centre (distorted pixel -> ray), iterated tightly:
  // the default 5 iterations leave errors of tenths of a pixel near the corners of wide lenses.
  std::vector<cv::Point2f> pixels;
  pixels.reserve(static_cast<std::size_t>(w) * h);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) pixels.emplace_back(static_cast<float>(u), static_cast<float>(v));
  }
  cv::Matx33d kcv;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) kcv(r, c) = k(r, c);
  }
  std::vector<cv::Point2f> rays;
  if (n == 0) {
    cv::undistortPoints(pixels, rays, kcv, cv::noArray());
  } else {
    cv::undistortPoints(
        pixels, rays, kcv, calibration.distortion, cv::noArray(), cv::noArray(),
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12));
  }
  ray_x_.resize(rays.size());
  ray_y_.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ray_x_[i] = rays[i].x;
    ray_y_[i] = rays[i].y;
  }

  // Sub-pixel rays at (+-1/4, +-1/4) from the centre rays by their local first derivatives
  // (central differences, one-sided at the border): the ray field is smooth, the second-order
  // error is ~(1/4)^2/2 |d2 ray / du2|, far below 1e-3 pixel for real lenses.
  sub_rays_.resize(8 * rays.size());
  const auto at = [&](const std::vector<float>& a, int u, int v) {
    return a[static_cast<std::size_t>(v) * w + u];
  };
  for (int v = 0; v < h; ++v) {
    const int v0 = std::max(v - 1, 0), v1 = std::min(v + 1, h - 1);
    for (int u = 0; u < w; ++u) {
      const int u0 = std::max(u - 1, 0), u1 = std::min(u + 1, w - 1);
      const float su = u1 > u0 ? 1.0f / static_cast<float>(u1 - u0) : 0.0f;
      const float sv = v1 > v0 ? 1.0f / static_cast<float>(v1 - v0) : 0.0f;
      const float dxu = (at(ray_x_, u1, v) - at(ray_x_, u0, v)) * su;
      const float dyu = (at(ray_y_, u1, v) - at(ray_y_, u0, v)) * su;
      const float dxv = (at(ray_x_, u, v1) - at(ray_x_, u, v0)) * sv;
      const float dyv = (at(ray_y_, u, v1) - at(ray_y_, u, v0)) * sv;
      float* out = &sub_rays_[8 * (static_cast<std::size_t>(v) * w + u)];
      int k = 0;
      for (const float dv : {-0.25f, 0.25f}) {
        for (const float du : {-0.25f, 0.25f}) {
          out[k++] = at(ray_x_, u, v) + du * dxu + dv * dxv;
          out[k++] = at(ray_y_, u, v) + du * dyu + dv * dyv;
        }
      }
    }
  }
}

Eigen::Vector2d GroundRenderer::ray(int u, int v) const {
  const std::size_t i = static_cast<std::size_t>(v) * calibration_.width + u;
  return {ray_x_[i], ray_y_[i]};
}

cv::Mat GroundRenderer::render(const GroundTexture& texture,
                               const Eigen::Isometry3d& world_from_body,
                               const RenderOptions& options, std::mt19937_64& rng) const {
  VDTNAV_CHECK(
      texture.image.empty() || texture.image.type() == CV_8UC1 || texture.image.type() == CV_8UC3,
      "GroundRenderer: the texture must be 8-bit grey or BGR");
  VDTNAV_CHECK(texture.image.empty() || texture.resolution > 0.0,
               "GroundRenderer: texture resolution must be > 0");
  VDTNAV_CHECK(options.supersampling == 1 || options.supersampling == 2,
               "GroundRenderer: supersampling must be 1 or 2");
  VDTNAV_CHECK(options.noise_sigma >= 0.0 && std::isfinite(options.noise_sigma),
               "GroundRenderer: noise_sigma must be >= 0");
  const int w = calibration_.width, h = calibration_.height;

  // Camera ray r = R_wb R_bc (x_n, y_n, 1) from the centre c = T_wb t_bc; the ground point is
  // g = c + t r with t = -c_z / r_z (r_z < 0: the ray points down).
  const Eigen::Isometry3d world_from_camera = world_from_body * rig_.body_from_camera;
  const Eigen::Matrix3f m = world_from_camera.linear().cast<float>();
  const Eigen::Vector3d c = world_from_camera.translation();
  // Texture pixel coordinates of g: col = (g_x - o_x)/res - 1/2, row = rows - 1/2 - (g_y -
  // o_y)/res.
  const float inv_res = texture.image.empty() ? 1.0f : static_cast<float>(1.0 / texture.resolution);
  const float col0 = static_cast<float>((c.x() - texture.origin.x()) / texture.resolution - 0.5);
  const float row0 = static_cast<float>(texture.image.rows - 0.5 -
                                        (c.y() - texture.origin.y()) / texture.resolution);
  const float cz = static_cast<float>(c.z());
  const float max_t2 =
      static_cast<float>(options.max_ground_distance * options.max_ground_distance);
  const float background = static_cast<float>(texture.background);
  const bool colour = texture.image.channels() == 3;

  const auto shade = [&](float xn, float yn) -> float {
    const float rx = m(0, 0) * xn + m(0, 1) * yn + m(0, 2);
    const float ry = m(1, 0) * xn + m(1, 1) * yn + m(1, 2);
    const float rz = m(2, 0) * xn + m(2, 1) * yn + m(2, 2);
    if (!(cz > 0.0f) || !(rz < -1e-6f)) return background;  // sky, or camera below the ground
    const float t = -cz / rz;
    if (t * t * (rx * rx + ry * ry + rz * rz) > max_t2) return background;
    if (texture.image.empty()) return background;
    const float cu = col0 + t * rx * inv_res;
    const float cv = row0 - t * ry * inv_res;
    return colour ? bilinear<3>(texture.image, cu, cv, background)
                  : bilinear<1>(texture.image, cu, cv, background);
  };

  cv::Mat image(h, w, CV_32F);
  const float gain = static_cast<float>(options.exposure_gain);
  const float offset = static_cast<float>(options.exposure_offset);
  for (int v = 0; v < h; ++v) {
    float* out = image.ptr<float>(v);
    for (int u = 0; u < w; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      float value = 0.0f;
      if (options.supersampling == 2) {
        const float* s = &sub_rays_[8 * i];
        value =
            0.25f * (shade(s[0], s[1]) + shade(s[2], s[3]) + shade(s[4], s[5]) + shade(s[6], s[7]));
      } else {
        value = shade(ray_x_[i], ray_y_[i]);
      }
      // Exposure, saturated like the sensor's ADC.
      out[u] = std::clamp(gain * value + offset, 0.0f, 255.0f);
    }
  }

  if (options.motion_blur_px > 1.0) {
    cv::filter2D(image, image, -1, motion_blur_kernel(options.motion_blur_px, options.blur_angle),
                 cv::Point(-1, -1), 0.0, cv::BORDER_REFLECT_101);
  }
  if (options.noise_sigma > 0.0) {
    // One draw from `rng` seeds OpenCV's ziggurat normal generator (a local cv::RNG, never the
    // global one): deterministic for a given rng state and ~6x faster than
    // std::normal_distribution per pixel.
    cv::RNG noise_rng(rng());
    cv::Mat noise(h, w, CV_32F);
    noise_rng.fill(noise, cv::RNG::NORMAL, 0.0, options.noise_sigma);
    image += noise;
  }
  cv::Mat out;
  image.convertTo(out, CV_8U);  // rounds and saturates
  return out;
}

}  // namespace vdtnav::uav_camera
