// The RGB-D ground-boundary front end (thesis 3.4.5) on frames rendered here with a known pose —
// pavement and grass meeting along two known lines, a box standing on the pavement — and on the
// real Kinect frames of ../shared/data: the boundary points fall on the known boundaries, the
// box's edges are pruned, the ground plane is recovered from wrong extrinsics, the Jacobian of
// the back-projection matches finite differences, the per-point covariance and the fitted
// plane's covariance (the tilt every point shares) are consistent by Monte Carlo, and bad input
// is refused with the reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/rgbd_ground/camera_mount.hpp"
#include "vdtnav/rgbd_ground/ground_boundaries.hpp"

namespace vdtnav::rgbd_ground {
namespace {

using camera::CameraCalibration;
using camera::PinholeCamera;

CameraCalibration test_calibration() {
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  c.camera_matrix << 525.0, 0.0, 319.5, 0.0, 525.0, 239.5, 0.0, 0.0, 1.0;
  c.distortion = {-0.05, 0.01, 0.0, 0.0, 0.0};
  return c;
}

/// A rear camera at `height`, 0.3 m behind the robot's origin, looking backwards and `tilt`
/// radians down (robot frame x forward, y left, z up; camera x right, y down, z forward).
Eigen::Isometry3d rear_camera(double tilt, double height) {
  return tilted_camera(Eigen::Vector3d(-0.3, 0.0, height), kPi, tilt);
}

// The scene, robot frame: grass where x < -2.5 or y > 1.0, pavement elsewhere; a box on the
// pavement over [-2.0, -1.6] x [-1.2, -0.6], 0.8 m tall.
constexpr double kLineX = -2.5, kLineY = 1.0;
const Eigen::AlignedBox3d kBox(Eigen::Vector3d(-2.0, -1.2, 0.0), Eigen::Vector3d(-1.6, -0.6, 0.8));

/// Distance on the ground to the boundary between the two surfaces.
double boundary_distance(const Eigen::Vector2d& p) {
  // Segment x = kLineX for y <= kLineY, segment y = kLineY for x >= kLineX.
  const double d1 = std::hypot(p.x() - kLineX, std::max(0.0, p.y() - kLineY));
  const double d2 = std::hypot(std::max(0.0, kLineX - p.x()), p.y() - kLineY);
  return std::min(d1, d2);
}

/// Renders colour and z-depth (sigma_z2 z^2 noise when sigma_z2 > 0) of the scene.
RgbdFrame render(const CameraCalibration& cal, const Eigen::Isometry3d& camera_to_robot,
                 double sigma_z2, std::mt19937& rng) {
  const PinholeCamera camera(cal);
  std::vector<Eigen::Vector2d> px;
  for (int v = 0; v < cal.height; ++v)
    for (int u = 0; u < cal.width; ++u) px.emplace_back(u, v);
  const std::vector<Eigen::Vector2d> rays = camera.undistort(px);
  cv::Mat colour(cal.height, cal.width, CV_8UC3), depth(cal.height, cal.width, CV_32F);
  std::normal_distribution<double> n01(0.0, 1.0);
  const Eigen::Vector3d o = camera_to_robot.translation();
  for (int v = 0; v < cal.height; ++v) {
    for (int u = 0; u < cal.width; ++u) {
      const Eigen::Vector2d& n = rays[static_cast<std::size_t>(v) * cal.width + u];
      const Eigen::Vector3d ray_c(n.x(), n.y(), 1.0);  // z = 1: the hit's t is its z-depth
      const Eigen::Vector3d d = camera_to_robot.linear() * ray_c;
      double t = std::numeric_limits<double>::infinity();
      cv::Vec3b c(235, 206, 135);  // sky (BGR)
      if (d.z() < 0.0) {
        t = -o.z() / d.z();
        const Eigen::Vector3d g = o + t * d;
        const bool grass = g.x() < kLineX || g.y() > kLineY;
        const double tex = 6.0 * n01(rng);
        c = grass
                ? cv::Vec3b(cv::saturate_cast<uchar>(50 + tex), cv::saturate_cast<uchar>(140 + tex),
                            cv::saturate_cast<uchar>(60 + tex))
                : cv::Vec3b(cv::saturate_cast<uchar>(130 + tex),
                            cv::saturate_cast<uchar>(128 + tex),
                            cv::saturate_cast<uchar>(126 + tex));
      }
      // The box, by slabs.
      double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
      for (int k = 0; k < 3; ++k) {
        const double a = (kBox.min()[k] - o[k]) / d[k], b = (kBox.max()[k] - o[k]) / d[k];
        t0 = std::max(t0, std::min(a, b));
        t1 = std::min(t1, std::max(a, b));
      }
      if (t0 <= t1 && t0 < t) {
        t = t0;
        c = cv::Vec3b(40, 40, 200);
      }
      colour.at<cv::Vec3b>(v, u) = c;
      double z = std::isfinite(t) && t < 10.0 ? t : 0.0;
      if (z > 0.0 && sigma_z2 > 0.0) z += sigma_z2 * z * z * n01(rng);
      depth.at<float>(v, u) = static_cast<float>(z);
    }
  }
  return make_rgbd_frame(colour, depth, 1.0);
}

struct Scene {
  CameraCalibration cal = test_calibration();
  Eigen::Isometry3d truth = rear_camera(35.0 * kPi / 180.0, 1.0);
  RgbdFrame frame;
  Scene() {
    std::mt19937 rng(1);
    frame = render(cal, truth, 0.0, rng);
  }
};
const Scene& scene() {
  static const Scene s;
  return s;
}

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

TEST(GroundBoundaries, PointsLieOnTheKnownBoundariesAndTheBoxIsPruned) {
  const GroundBoundaryExtractor ex(PinholeCamera(scene().cal), scene().truth);
  const GroundBoundaries b = ex.extract(scene().frame);
  ASSERT_TRUE(b.plane.found);
  std::vector<double> dist;
  int on_x = 0, on_y = 0;
  for (const BoundaryPoint& p : b.points) {
    dist.push_back(boundary_distance(p.robot));
    on_x += std::abs(p.robot.x() - kLineX) < 0.05 && p.robot.y() < kLineY - 0.1;
    on_y += std::abs(p.robot.y() - kLineY) < 0.05 && p.robot.x() > kLineX + 0.1;
    // Nothing kept on or beside the box.
    EXPECT_FALSE(p.robot.x() > -2.1 && p.robot.x() < -1.5 && p.robot.y() > -1.3 &&
                 p.robot.y() < -0.5)
        << p.robot.transpose();
  }
  ASSERT_GT(dist.size(), 200u);
  EXPECT_GT(on_x, 80);  // both boundaries are seen
  EXPECT_GT(on_y, 80);
  // Canny on a blurred image places an edge within a pixel: ~1-2 cm on the ground at 2-4 m.
  EXPECT_LT(percentile(dist, 0.5), 0.015);
  EXPECT_LT(percentile(dist, 0.95), 0.04);
  EXPECT_GT(b.pruned, 100);  // the box's outline against pavement and sky
}

TEST(GroundBoundaries, ThePlaneComesFromTheDepthNotFromWrongExtrinsics) {
  // Extrinsics off by 3 degrees of tilt and 5 cm of height.
  const Eigen::Isometry3d wrong = rear_camera(38.0 * kPi / 180.0, 1.05);
  const GroundBoundaryExtractor ex(PinholeCamera(scene().cal), wrong);
  const GroundBoundaries b = ex.extract(scene().frame);
  ASSERT_TRUE(b.plane.found);
  const GroundPlane truth = expected_ground_plane(scene().truth);
  EXPECT_LT(std::acos(std::min(1.0, b.plane.normal.dot(truth.normal))), 0.5 * kPi / 180.0);
  EXPECT_NEAR(b.plane.offset, truth.offset, 0.01);
  std::vector<double> dist;
  for (const BoundaryPoint& p : b.points) dist.push_back(boundary_distance(p.robot));
  ASSERT_GT(dist.size(), 200u);
  EXPECT_LT(percentile(dist, 0.5), 0.015);
  // The nominal extrinsics would put the same pixels ~10-20 cm off.
  const GroundBoundaryExtractor nominal(PinholeCamera(scene().cal), wrong);
  std::vector<double> off;
  for (const BoundaryPoint& p : b.points) {
    off.push_back(boundary_distance(
        nominal.back_project(p.pixel.cast<double>(), p.camera.z(), wrong, nullptr)));
  }
  EXPECT_GT(percentile(off, 0.5), 0.05);
}

TEST(GroundBoundaries, BackProjectionJacobianMatchesFiniteDifferences) {
  const GroundBoundaryExtractor ex(PinholeCamera(scene().cal), scene().truth);
  for (const auto& [u, v, z] : {std::tuple{100.0, 400.0, 2.2}, std::tuple{600.0, 300.0, 3.7},
                                std::tuple{320.0, 240.0, 2.9}}) {
    Eigen::Matrix<double, 2, 3> j;
    (void)ex.back_project({u, v}, z, scene().truth, &j);
    const double h[3] = {1e-3, 1e-3, 1e-6};
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d a(u, v, z), b(u, v, z);
      a[k] += h[k];
      b[k] -= h[k];
      const Eigen::Vector2d fd = (ex.back_project(a.head<2>(), a.z(), scene().truth, nullptr) -
                                  ex.back_project(b.head<2>(), b.z(), scene().truth, nullptr)) /
                                 (2.0 * h[k]);
      EXPECT_LT((j.col(k) - fd).norm(), 1e-6 * std::max(1.0, fd.norm())) << "column " << k;
    }
  }
}

TEST(GroundBoundaries, PointCovarianceIsConsistentByMonteCarlo) {
  // Pixel and depth noise drawn as the model says, pushed through the back-projection: the NEES
  // of the resulting points under the reported covariance has mean 2 (chi-square, 2 dof); over
  // 20 points x 500 draws the 99 % interval of the mean is about [1.94, 2.06] when linear.
  const GroundBoundaryExtractor ex(PinholeCamera(scene().cal), scene().truth);
  const GroundBoundaries b = ex.extract(scene().frame);
  ASSERT_GT(b.points.size(), 20u);
  const DepthNoiseModel& noise = ex.options().noise;
  std::mt19937 rng(3);
  std::normal_distribution<double> n01(0.0, 1.0);
  double nees = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < b.points.size(); i += b.points.size() / 20) {
    const BoundaryPoint& p = b.points[i];
    const double z = p.camera.z();
    const Eigen::Vector2d mean = ex.back_project(p.pixel.cast<double>(), z, scene().truth, nullptr);
    const Eigen::Matrix2d info = p.covariance.inverse();
    for (int d = 0; d < 500; ++d) {
      const Eigen::Vector2d px =
          p.pixel.cast<double>() + noise.sigma_pixel * Eigen::Vector2d(n01(rng), n01(rng));
      const double zz = z + noise.sigma_z(z) * n01(rng);
      const Eigen::Vector2d e = ex.back_project(px, zz, scene().truth, nullptr) - mean;
      nees += e.dot(info * e);
      ++count;
    }
  }
  nees /= count;
  EXPECT_GT(nees, 1.9);
  EXPECT_LT(nees, 2.1);
}

/// Mean NEES of the fitted plane's tilt (2 dof, through levelled_tilt_covariance) and offset
/// (1 dof) over `trials` noisy copies of the bare ground's depth (the scene without its box,
/// whose faces' lowest 2 cm would pass as ground and bias the fit by ~2 sigma), the noise
/// `truth_factor` times the model's sigma_z (drawn at the pixels the fit samples: stride 6 from 3).
std::pair<double, double> plane_nees(double truth_factor, int trials) {
  const PinholeCamera camera(scene().cal);
  const DepthNoiseModel model;
  const GroundPlaneOptions options;
  cv::Mat ground(scene().cal.height, scene().cal.width, CV_32F, cv::Scalar(0.0f));
  {
    std::vector<Eigen::Vector2d> px;
    for (int v = 0; v < ground.rows; ++v)
      for (int u = 0; u < ground.cols; ++u) px.emplace_back(u, v);
    const std::vector<Eigen::Vector2d> rays = camera.undistort(px);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const Eigen::Vector3d d =
          scene().truth.linear() * Eigen::Vector3d(rays[i].x(), rays[i].y(), 1.0);
      const double z = d.z() < 0.0 ? -scene().truth.translation().z() / d.z() : 0.0;
      ground.at<float>(static_cast<int>(px[i].y()), static_cast<int>(px[i].x())) =
          static_cast<float>(z < 10.0 ? z : 0.0);
    }
  }
  std::mt19937 rng(11);
  std::normal_distribution<double> n01(0.0, 1.0);
  double tilt = 0.0, offset = 0.0;
  for (int t = 0; t < trials; ++t) {
    cv::Mat depth = ground.clone();
    for (int v = options.stride / 2; v < depth.rows; v += options.stride) {
      for (int u = options.stride / 2; u < depth.cols; u += options.stride) {
        float& z = depth.at<float>(v, u);
        if (z > 0.0f) z += static_cast<float>(truth_factor * model.sigma_z(z) * n01(rng));
      }
    }
    const RgbdFrame frame = make_rgbd_frame(scene().frame.colour, depth, 1.0);
    const GroundPlane plane = fit_ground_plane(frame, camera, scene().truth, model, options);
    EXPECT_TRUE(plane.found);
    const Eigen::Isometry3d levelled = levelled_extrinsics(scene().truth, plane);
    // The tilt left on the levelled rotation: R_true = Exp(delta) R'.
    const Eigen::AngleAxisd e(scene().truth.linear() * levelled.linear().transpose());
    const Eigen::Vector2d delta = (e.angle() * e.axis()).head<2>();
    tilt += delta.dot(levelled_tilt_covariance(levelled, plane).inverse() * delta);
    offset += std::pow((plane.offset - scene().truth.translation().z()) / plane.offset_sigma, 2);
  }
  return {tilt / trials, offset / trials};
}

TEST(GroundBoundaries, ThePlanesCovarianceIsConsistentByMonteCarlo) {
  // 300 noisy frames: the mean NEES of the tilt (chi-square, 2 dof) has the 99 % interval
  // 2 +- 2.58 sqrt(4 / 300) = [1.70, 2.30], the offset's (1 dof) 1 +- 2.58 sqrt(2 / 300) =
  // [0.79, 1.21]. Leaving out the ray's angle to the plane in sigma_i (|n . ray| ~ 0.3-1 here)
  // would inflate the covariance and fail the lower ends.
  const auto [tilt, offset] = plane_nees(1.0, 300);
  std::printf("plane NEES: tilt %.3f, offset %.3f\n", tilt, offset);
  EXPECT_GT(tilt, 1.70);
  EXPECT_LT(tilt, 2.30);
  EXPECT_GT(offset, 0.79);
  EXPECT_LT(offset, 1.21);
}

TEST(GroundBoundaries, AGroundRougherThanTheDepthNoiseScalesThePlanesCovarianceUp) {
  // The depth scatters twice as much as the noise model says (a rough ground, a noisier sensor):
  // the reduced chi-square of the fit scales the covariance, the NEES stays near its dof (the
  // inlier distance, 3 model sigmas = 1.5 true ones, trims the tails: a looser bound, 0.7-1.3x);
  // without the scale it would be ~4x its dof.
  const auto [tilt, offset] = plane_nees(2.0, 300);
  std::printf("plane NEES, depth noise 2x the model's: tilt %.3f, offset %.3f\n", tilt, offset);
  EXPECT_GT(tilt, 0.7 * 2.0);
  EXPECT_LT(tilt, 1.3 * 2.0);
  EXPECT_GT(offset, 0.7);
  EXPECT_LT(offset, 1.3);
}

TEST(GroundBoundaries, EveryPointSharesThePlanesTiltAndTheObservationsCarryIt) {
  const GroundBoundaryExtractor ex(PinholeCamera(scene().cal), scene().truth);
  const GroundBoundaries b = ex.extract(scene().frame);
  ASSERT_GT(b.points.size(), 20u);
  ASSERT_GT(b.tilt_covariance.trace(), 0.0);
  const Eigen::Isometry3d levelled = levelled_extrinsics(scene().truth, b.plane);
  // Finite differences of the back-projection under the tilted extrinsics Exp(delta) R'.
  for (std::size_t i = 0; i < b.points.size(); i += b.points.size() / 10) {
    const BoundaryPoint& p = b.points[i];
    for (int k = 0; k < 2; ++k) {
      const double h = 1e-5;
      Eigen::Isometry3d plus = levelled, minus = levelled;
      plus.linear() = Eigen::AngleAxisd(h, Eigen::Vector3d::Unit(k)) * levelled.linear();
      minus.linear() = Eigen::AngleAxisd(-h, Eigen::Vector3d::Unit(k)) * levelled.linear();
      const Eigen::Vector2d fd =
          (ex.back_project(p.pixel.cast<double>(), p.camera.z(), plus, nullptr) -
           ex.back_project(p.pixel.cast<double>(), p.camera.z(), minus, nullptr)) /
          (2.0 * h);
      EXPECT_LT((p.tilt_jacobian.col(k) - fd).norm(), 1e-6) << "point " << i << " column " << k;
      // On the ground: the camera's height times the tilt, the same for every point.
      EXPECT_NEAR(fd.norm(), b.plane.offset, 0.02) << "point " << i;
    }
  }
  const ScanPoints obs = ex.observations(b);
  ASSERT_EQ(obs.num_shared(), 2);
  EXPECT_EQ(obs.shared_covariance, Eigen::MatrixXd(b.tilt_covariance));
  for (std::size_t i = 0; i < obs.size(); ++i) {
    ASSERT_EQ(Eigen::Matrix2d(obs.shared_jacobians[i]), b.points[obs.beam[i]].tilt_jacobian);
  }
}

TEST(GroundBoundaries, EdgeTangentsFollowTheKnownBoundariesAndCornersAreNotStraight) {
  const GroundBoundaryExtractor ex(PinholeCamera(scene().cal), scene().truth);
  const GroundBoundaries b = ex.extract(scene().frame);
  int along_x = 0, along_y = 0, corner = 0;
  for (const BoundaryPoint& p : b.points) {
    const double to_corner = (p.robot - Eigen::Vector2d(kLineX, kLineY)).norm();
    if (std::abs(p.robot.x() - kLineX) < 0.05 && p.robot.y() < kLineY - 0.3) {
      ++along_x;  // the line x = kLineX runs along y
      EXPECT_GT(std::abs(p.tangent.y()), 0.98) << p.robot.transpose();
      EXPECT_GT(p.straightness, 0.95) << p.robot.transpose();
    } else if (std::abs(p.robot.y() - kLineY) < 0.05 && p.robot.x() > kLineX + 0.3) {
      ++along_y;
      EXPECT_GT(std::abs(p.tangent.x()), 0.98) << p.robot.transpose();
      EXPECT_GT(p.straightness, 0.95) << p.robot.transpose();
    } else if (to_corner < 0.03) {
      ++corner;  // an L: its arms (unequal in points, by perspective) pull both ways
      EXPECT_LT(p.straightness, 0.75) << p.robot.transpose();
    }
  }
  EXPECT_GT(along_x, 50);
  EXPECT_GT(along_y, 50);
  EXPECT_GT(corner, 0);
  // The observations carry the aperture term along the edge, the points' own covariance across.
  const ScanPoints obs = ex.observations(b);
  ASSERT_EQ(obs.size(), b.points.size());
  const double a = ex.options().aperture_sigma;
  for (std::size_t i = 0; i < b.points.size(); ++i) {
    const BoundaryPoint& p = b.points[i];
    const Eigen::Vector2d n(-p.tangent.y(), p.tangent.x());
    EXPECT_NEAR(n.dot(obs.point_covariances[i] * n), n.dot(p.covariance * n), 1e-12);
    EXPECT_NEAR(p.tangent.dot(obs.point_covariances[i] * p.tangent),
                p.tangent.dot(p.covariance * p.tangent) + std::pow(p.straightness * a, 2), 1e-9);
  }
}

TEST(GroundBoundaries, SparseFarEdgePointsStillHaveTheirEdgesDirection) {
  // Far from the camera the kept pixels of an edge lie farther apart than aperture_radius (a
  // pixel row spans z^2 / (f h) on the ground: 14 cm at 6 m for a camera 1 m up, stride 2): the
  // neighbourhood grows to the 6th nearest, so these points are not taken as isolated (which
  // would give them full information along the edge).
  std::vector<BoundaryPoint> pts;
  const Eigen::Vector2d t = Eigen::Vector2d(2.0, 1.0).normalized();
  for (int k = 0; k < 20; ++k) {
    BoundaryPoint p;
    p.robot = Eigen::Vector2d(-6.0, 0.0) + 0.2 * k * t;
    pts.push_back(p);
  }
  estimate_edge_tangents(pts, 0.15);
  for (const BoundaryPoint& p : pts) {
    EXPECT_GT(p.straightness, 0.99);
    EXPECT_GT(std::abs(p.tangent.dot(t)), 0.999);
  }
}

TEST(GroundBoundaries, AStraightEdgeInAGridMapTellsNothingAlongItself) {
  // A boundary at a slope of 0.066 drawn in a 5 cm grid as a two-cell band (a staircase of
  // 15-cell steps, as the park's bent paths are): its cells ripple along the line, and without the
  // aperture term 400 points on it made the EKF believe it knew the position along the line to
  // ~1 cm (the along-track collapse of examples/pmd_rgbd). The points lie exactly on the true line;
  // the prior along the line must survive the update, across it the points must win.
  const double res = 0.05, slope = 0.066;
  const auto line_y = [&](double x) { return 3.0 + slope * (x - 2.0); };
  OccupancyGrid<2> grid(Eigen::Vector2i(400, 200), GridFrame<2>(res, Eigen::Vector2d::Zero()), 0);
  const auto above = [&](int x, int y) {
    const Eigen::Vector2d c = grid.cell_center({x, y});
    return c.y() > line_y(c.x());
  };
  for (int y = 0; y + 1 < 200; ++y)
    for (int x = 0; x + 1 < 400; ++x)
      for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}})
        if (above(x, y) != above(x + dx, y + dy)) {
          grid({x, y}) = 1;
          grid({x + dx, y + dy}) = 1;
        }
  const VdtMap2 map = VdtMap2::build(grid);
  const Pose2 pose(10.0, line_y(10.0) - 1.0, 0.0);
  std::vector<BoundaryPoint> points;
  for (double x = 6.0; x <= 14.0; x += 0.02) {
    BoundaryPoint p;
    p.robot = Eigen::Vector2d(x, line_y(x)) - pose.head<2>();
    p.covariance = Eigen::Vector2d(1e-4, 1e-4).asDiagonal();
    points.push_back(p);
  }
  estimate_edge_tangents(points, 0.15);
  GroundBoundaries b;
  b.points = points;
  const Eigen::Vector2d t = Eigen::Vector2d(1.0, slope).normalized(), n(-t.y(), t.x());
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.01, 0.01, 1e-4).asDiagonal();
  // The filter's covariance and the one it reports (with the map term of 2 m squares, as in
  // examples/pmd_rgbd, when correlation_length > 0).
  const auto posterior = [&](double aperture_sigma, double correlation_length) {
    GroundBoundaryOptions o;
    o.aperture_sigma = aperture_sigma;
    const GroundBoundaryExtractor ex(PinholeCamera(scene().cal), scene().truth, o);
    VdtEkfOptions eo;
    eo.motion = MotionModelKind::kOdometryIncrement;
    eo.search.enabled = false;
    eo.sensor.gate = 5.0 * res;
    eo.sensor.map_sigma = 0.5 * res;
    eo.sensor.map_correlation_length = correlation_length;
    eo.sensor.map_pose_sigma = 0.0;
    VdtEkfLocalizer ekf(map, eo);
    ekf.reset(pose, p0);
    (void)ekf.update(OdometryStep{}, ex.observations(b));
    return std::pair{ekf.covariance(), ekf.reported_covariance()};
  };
  const Eigen::Matrix3d with = posterior(10.0, 0.0).first, without = posterior(0.0, 0.0).first;
  const auto sd = [](const Eigen::Matrix3d& p, const Eigen::Vector2d& u) {
    return std::sqrt(u.dot(p.topLeftCorner<2, 2>() * u));
  };
  EXPECT_GT(sd(with, t), 0.8 * 0.1);  // along: the prior's 10 cm, nearly untouched
  EXPECT_LT(sd(without, t), 0.05);    // the collapse this guards against
  // Across, the line is still found: to within the staircase's half cell, not the prior's 10 cm.
  EXPECT_LT(sd(with, n), 0.5 * res);
  // The map's squares: the frame barely observes the along-track direction, so their errors
  // cannot move the estimate along it by more than the prior allows (the reported covariance
  // stays within the prior's 10 cm and a square's 2.5 cm; on the frames of a real drive, where it
  // once exploded, test_park_drive_covariance).
  const auto [filter, reported] = posterior(10.0, 2.0);
  EXPECT_LT(sd(reported, t), std::hypot(0.1, 0.5 * res));
  EXPECT_GE(sd(reported, t), sd(filter, t));
  EXPECT_LT(sd(reported, n), 0.5 * res);
}

TEST(GroundBoundaries, BadInputIsRefusedWithTheReason) {
  const cv::Mat colour(480, 640, CV_8UC3, cv::Scalar(100, 100, 100));
  const cv::Mat depth(480, 640, CV_16U, cv::Scalar(2000));
  // Sizes differ.
  try {
    (void)make_rgbd_frame(colour, cv::Mat(240, 320, CV_16U, cv::Scalar(2000)), 1000.0);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("differ in size"), std::string::npos) << e.what();
  }
  // All-zero depth.
  try {
    (void)make_rgbd_frame(colour, cv::Mat(480, 640, CV_16U, cv::Scalar(0)), 1000.0);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("all zero"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)make_rgbd_frame(colour, depth, 0.0), ConfigError);  // no depth scale
  EXPECT_THROW((void)make_rgbd_frame(colour, cv::Mat(480, 640, CV_8U, cv::Scalar(5)), 1.0),
               ConfigError);  // 8-bit depth
  // Files: missing, and a colour image given as depth.
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "vdtnav_rgbd_test";
  std::filesystem::create_directories(dir);
  const std::string c = (dir / "c.png").string(), d = (dir / "d.png").string();
  cv::imwrite(c, colour);
  cv::imwrite(d, depth);
  EXPECT_NO_THROW((void)read_rgbd_frame(c, d, 1000.0));
  EXPECT_THROW((void)read_rgbd_frame(c, (dir / "missing.png").string(), 1000.0), IoError);
  try {
    (void)read_rgbd_frame(c, c, 1000.0);
    ADD_FAILURE() << "no error";
  } catch (const FormatError& e) {
    EXPECT_EQ(e.file(), c);
  }
  // Missing intrinsics.
  EXPECT_THROW((void)camera::read_calibration((dir / "no_such_camera.yaml").string()), IoError);
  // A frame of another size than the camera's.
  const GroundBoundaryExtractor ex(PinholeCamera(scene().cal), scene().truth);
  EXPECT_THROW(
      (void)ex.extract(make_rgbd_frame(cv::Mat(240, 320, CV_8UC3, cv::Scalar(1, 2, 3)),
                                       cv::Mat(240, 320, CV_16U, cv::Scalar(900)), 1000.0)),
      ConfigError);
}

TEST(GroundBoundaries, CameraPosesReadBackAndBadLinesNameTheirLine) {
  const std::string dir = std::string(VDTNAV_TEST_TMP);
  std::filesystem::create_directories(dir);
  const std::string good = dir + "/poses_good.txt", bad = dir + "/poses_bad.txt";
  {
    std::ofstream f(good);
    // A quarter turn about z (qz = qw = sqrt(1/2)) at (1, 2, 3), a blank line, the identity.
    f << "1 2 3 0 0 0.7071067811865476 0.7071067811865476\n\n-1 0 0.5 0 0 0 1\n";
  }
  const std::vector<Eigen::Isometry3d> poses = read_camera_poses(good);
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_TRUE(poses[0].translation().isApprox(Eigen::Vector3d(1.0, 2.0, 3.0)));
  // Camera-to-world: the camera's x axis points along the world's y.
  EXPECT_TRUE((poses[0].linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_TRUE(poses[1].linear().isApprox(Eigen::Matrix3d::Identity()));
  {
    std::ofstream f(bad);
    f << "0 0 0 0 0 0 1\n0 0 0 0 0 nan 1\n";
  }
  try {
    (void)read_camera_poses(bad);
    ADD_FAILURE() << "a NaN was read";
  } catch (const FormatError& e) {
    EXPECT_EQ(e.line(), 2u);
    EXPECT_NE(std::string(e.what()).find("expected 7 numbers"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)read_camera_poses(dir + "/no_such_file.txt"), IoError);
}

TEST(GroundBoundaries, RealKinectFramesGiveOneFloorThroughTheGivenPoses) {
  const std::string dir = std::string(VDTNAV_DATA_DIR) + "/vision/rgbd-kinect";
  if (!std::filesystem::exists(dir + "/pose.txt")) GTEST_SKIP() << "real data absent: " << dir;
  CameraCalibration cal;
  cal.width = 640;
  cal.height = 480;
  cal.camera_matrix << 518.0, 0.0, 325.5, 0.0, 519.0, 253.5, 0.0, 0.0, 1.0;
  const std::vector<Eigen::Isometry3d> poses = read_camera_poses(dir + "/pose.txt");
  ASSERT_EQ(poses.size(), 5u);
  // Nominal mounting: a hand-held camera ~1.4 m up, looking forward and ~25 degrees down; the
  // fit may move it by up to 0.6 rad and 0.4 m.
  const Eigen::Isometry3d nominal =
      tilted_camera(Eigen::Vector3d(0.0, 0.0, 1.4), 0.0, 25.0 * kPi / 180.0);
  GroundBoundaryOptions o;
  o.plane.max_tilt = 0.6;
  o.use_lightness = true;  // indoors, a carpet's edges are edges of lightness too
  const GroundBoundaryExtractor ex(PinholeCamera(cal), nominal, o);
  std::vector<Eigen::Vector3d> normals;
  std::vector<double> offsets;
  for (int i = 1; i <= 5; ++i) {
    const RgbdFrame f = read_rgbd_frame(dir + "/color/" + std::to_string(i) + ".png",
                                        dir + "/depth/" + std::to_string(i) + ".pgm", 1000.0);
    const GroundBoundaries b = ex.extract(f);
    ASSERT_TRUE(b.plane.found) << "frame " << i;
    EXPECT_GT(b.plane.inliers, 1000) << "frame " << i;  // the floor fills a third of the image
    EXPECT_GT(b.points.size(), 20u) << "frame " << i;   // floor boundaries kept
    EXPECT_GT(b.pruned, 0) << "frame " << i;            // chair and table legs pruned
    // The floor in the world: n_w = R n_c, offset_w = offset - n_w . t.
    const Eigen::Vector3d n = poses[static_cast<std::size_t>(i - 1)].linear() * b.plane.normal;
    normals.push_back(n);
    offsets.push_back(b.plane.offset - n.dot(poses[static_cast<std::size_t>(i - 1)].translation()));
    std::printf(
        "frame %d: height %.3f m, rms %.3f m, %d inliers, %zu points, %d pruned, world "
        "normal (%.3f %.3f %.3f) offset %.3f\n",
        i, b.plane.offset, b.plane.rms, b.plane.inliers, b.points.size(), b.pruned, n.x(), n.y(),
        n.z(), offsets.back());
  }
  // One floor: against the frames' median (the poses are a reference with centimetres of error:
  // the README measures 3-10 cm of depth disagreement between frames warped through them). A
  // table top or a wall taken for the floor is 20+ degrees or 0.25+ m off.
  Eigen::Vector3d mean_normal = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& n : normals) mean_normal += n;
  mean_normal.normalize();
  std::vector<double> sorted = offsets;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  for (std::size_t i = 0; i < normals.size(); ++i) {
    EXPECT_LT(std::acos(std::min(1.0, normals[i].dot(mean_normal))), 3.0 * kPi / 180.0) << i;
    EXPECT_NEAR(offsets[i], median, 0.06) << i;
  }
}

TEST(GroundBoundaries, IclFramesFindTheFloorStripFromExtrinsicsFiveDegreesOff) {
  // Rendered ICL-NUIM frames with exact poses; a floor strip at the bottom of frames 1, 3 and 5
  // (a sofa seat fills more of the view than the strip in frame 1; the camera is 1.39, 0.95 and
  // 1.37 m up and rolled up to 18 degrees). fy = -480 in the dataset (camera y up): the usual
  // y-down camera is fy = +480 with the pose's rotation times diag(1, -1, 1); the world is y-up
  // with the floor at y = -1.38 (README of the data).
  const std::string dir = std::string(VDTNAV_DATA_DIR) + "/vision/rgbd-icl";
  if (!std::filesystem::exists(dir + "/pose.txt")) GTEST_SKIP() << "data absent: " << dir;
  CameraCalibration cal;
  cal.width = 640;
  cal.height = 480;
  cal.camera_matrix << 481.2, 0.0, 319.5, 0.0, 480.0, 239.5, 0.0, 0.0, 1.0;
  std::vector<Eigen::Isometry3d> poses = read_camera_poses(dir + "/pose.txt");
  ASSERT_EQ(poses.size(), 5u);
  // World (y up, floor at y = -1.38) to a robot frame on the floor (z up).
  Eigen::Isometry3d world_to_robot = Eigen::Isometry3d::Identity();
  world_to_robot.linear() << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  world_to_robot.translation() = Eigen::Vector3d(0.0, 0.0, 1.38);
  GroundBoundaryOptions o;
  o.use_lightness = true;  // indoors, edges of lightness are edges too
  for (int i : {1, 3, 5}) {
    Eigen::Isometry3d& t = poses[static_cast<std::size_t>(i - 1)];
    t.linear() = t.linear() * Eigen::Vector3d(1.0, -1.0, 1.0).asDiagonal();
    // The extrinsics the extractor is given: the true ones tilted 5 degrees and raised 15 cm.
    Eigen::Isometry3d given = world_to_robot * t;
    given.linear() =
        given.linear() * Eigen::AngleAxisd(5.0 * kPi / 180.0, Eigen::Vector3d::UnitX());
    given.translation().z() += 0.15;
    const GroundBoundaryExtractor ex(PinholeCamera(cal), given, o);
    const RgbdFrame f = read_rgbd_frame(dir + "/color/" + std::to_string(i) + ".png",
                                        dir + "/depth/" + std::to_string(i) + ".png", 5000.0);
    const GroundBoundaries b = ex.extract(f);
    ASSERT_TRUE(b.plane.found) << "frame " << i;
    // The fitted floor in the world: n_w = R n_c, offset_w = offset - n_w . t.
    const Eigen::Vector3d n = t.linear() * b.plane.normal;
    const double offset = b.plane.offset - n.dot(t.translation());
    std::printf(
        "frame %d: height %.3f m, %d inliers, %zu points, %d pruned, world normal "
        "(%.3f %.3f %.3f) offset %.3f\n",
        i, b.plane.offset, b.plane.inliers, b.points.size(), b.pruned, n.x(), n.y(), n.z(), offset);
    EXPECT_LT(std::acos(std::min(1.0, n.y())), 3.0 * kPi / 180.0) << "frame " << i;
    EXPECT_NEAR(offset, 1.38, 0.03) << "frame " << i;  // the seat is 0.5 m higher
    EXPECT_GT(b.pruned, 1000) << "frame " << i;        // sofa, lamp, plant, walls
    if (i != 5) {                                      // 5: a plain strip
      EXPECT_GT(b.points.size(), 20u) << "frame " << i;
    }
  }
}

}  // namespace
}  // namespace vdtnav::rgbd_ground
