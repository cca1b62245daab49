// Localization on what the UAV's downward camera sees (thesis 3.4.3), against independent oracles:
// a rendered image with a known pose for the whole front end, finite differences for the sensor
// model's cross derivative, Monte Carlo NEES for the covariances with the errors every point of a
// frame shares (roll, pitch, laser range), and the localizers' behaviour when the markings leave
// the view, come back, or the readings are unusable.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "vdtnav/camera_sim/ground_renderer.hpp"
#include "vdtnav/camera_sim/runway_scene.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/uav_camera/marking_map.hpp"
#include "vdtnav/uav_camera/uav_camera_front_end.hpp"

namespace vdtnav::uav_camera {
namespace {

constexpr double kDeg = kPi / 180.0;

/// The example's camera: 640 x 480, 60 degree horizontal field of view, mild barrel distortion.
CameraCalibration distorted_camera() {
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  const double f = 0.5 * c.width / std::tan(0.5 * 60.0 * kDeg);  // 554 px
  c.camera_matrix << f, 0.0, 319.5, 0.0, f, 239.5, 0.0, 0.0, 1.0;
  c.distortion = {-0.12, 0.03, 0.0005, -0.0003, 0.0};
  return c;
}

/// Exact readings at roll, pitch and altitude h: the default rig's laser points along body -z from
/// the body origin, so it measures h / (cos roll cos pitch).
AttitudeReading exact_reading(double roll, double pitch, double h) {
  return {roll, pitch, h / (std::cos(roll) * std::cos(pitch))};
}

struct Scene {
  RunwayScene scene;
  OccupancyGrid<2> boundaries;
  VdtMap2 map;
};

/// The default runway geometry with a narrow grass margin (a smaller texture, same markings).
const Scene& runway() {
  static const Scene s = [] {
    RunwaySceneOptions o;
    o.grass_margin = 4.0;
    Scene r;
    r.scene = make_runway_scene(o);
    r.boundaries = marking_boundaries(r.scene.markings);
    r.map = VdtMap2::build(r.boundaries);
    return r;
  }();
  return s;
}

/// The pose of the road's centreline at index i, heading along it.
Pose2 road_pose(const std::vector<Eigen::Vector2d>& line, std::size_t i) {
  const std::size_t n = line.size();
  const Eigen::Vector2d d = line[(i + 1) % n] - line[(i + n - 1) % n];
  return {line[i % n].x(), line[i % n].y(), std::atan2(d.y(), d.x())};
}

/// Options of the example (examples/uav_camera/uav_camera.cpp) for a map of resolution `res` at
/// altitude `h`: at least 50 explained edge points, a 10-cell gate, the window search.
GuessSearchOptions example_search(double res, double h, const MotionNoise& odo) {
  GuessSearchOptions s;
  s.explained_distance = 2.0 * res + h * 0.2 * kDeg;
  s.search_below = 0.5;
  s.accept_fraction = 0.25;
  s.reentry_fraction = 0.4;
  s.truncation = 0.5;
  s.max_window_xy = 6.0;
  s.max_window_yaw = 0.6;
  s.odometry_noise = odo;
  return s;
}

MotionNoise example_odometry_noise() {
  MotionNoise odo;  // 5 % of the distance per axis, 5 % of the turn + 0.005 rad/s in yaw
  odo.a_tt = 0.05;
  odo.a_tr = 0.0;
  odo.a_rr = 0.05;
  odo.a_rt = 0.0;
  odo.floor_t = 1e-4;
  odo.floor_r = 0.005 / 10.0;
  return odo;
}

VdtOptimizerOptions example_optimizer(double res, double h) {
  VdtOptimizerOptions o;
  o.sensor.gate = 10.0 * res;
  o.min_inliers = 50;
  o.search = example_search(res, h, example_odometry_noise());
  o.bridge.enabled = false;
  return o;
}

VdtEkfOptions example_ekf(double res, double h) {
  VdtEkfOptions o;
  o.sensor.gate = 10.0 * res;
  o.min_inliers = 50;
  o.motion = MotionModelKind::kOdometryIncrement;
  o.noise = example_odometry_noise();
  o.search = example_search(res, h, o.noise);
  o.max_iterations = 5;
  return o;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// ---------------------------------------------------------------------------------------------
// a. The whole front end on a rendered image with a known pose.

TEST(UavLocalization, RenderedEdgesProjectOntoTheMarkingBoundariesAtTheTruePose) {
  const Scene& s = runway();
  const CameraCalibration cal = distorted_camera();
  const UavRig rig;
  const GroundRenderer renderer(cal, rig);
  const UavCameraFrontEnd front(cal, rig);
  const double h = 15.0, roll = 3.0 * kDeg, pitch = -2.0 * kDeg;
  // Over the straight leg of the eight, 10 m from the crossing: two edge lines, the dashed centre
  // line, and the asphalt/grass border in view.
  const Pose2 truth = road_pose(s.scene.centreline, 100);
  std::mt19937_64 rng(7);
  const cv::Mat image = renderer.render(
      s.scene.texture, body_pose(truth[0], truth[1], h, roll, pitch, truth[2]), {}, rng);
  const CameraFrame frame = front.observe(image, exact_reading(roll, pitch, h));
  ASSERT_TRUE(frame.rejected.empty()) << frame.rejected;
  ASSERT_GE(frame.observations.size(), 500u);

  // Distance of each edge point, mapped to the world by the true (x, y, yaw), to the nearest
  // marking-boundary cell centre. A boundary cell's centre lies half a cell inside the paint, so
  // a perfect edge point is res / 2 from it; pixel quantisation adds up to GSD / 2. The asphalt's
  // cracks are edges too, which the map leaves out by design: the accuracy is measured on the edge
  // pixels next to white paint in the image (grey > 170 within 3 px; asphalt and grass are < 130),
  // a classification that does not use the projection.
  cv::Mat brightest;
  cv::dilate(image, brightest, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(7, 7)));
  std::vector<double> paint, all;
  for (std::size_t i = 0; i < frame.observations.size(); ++i) {
    bool inside = false;
    const Eigen::Vector2d d =
        s.map.value(transform_point(truth, frame.observations.points[i]), &inside);
    ASSERT_TRUE(inside);
    all.push_back(d.norm());
    const Eigen::Vector2d e = frame.edges[frame.observations.beam[i]];
    if (brightest.at<std::uint8_t>(static_cast<int>(std::lround(e.y())),
                                   static_cast<int>(std::lround(e.x()))) > 170) {
      paint.push_back(d.norm());
    }
  }
  const double gsd = h / cal.camera_matrix(0, 0);  // 2.7 cm per pixel at 15 m
  const double res = s.map.resolution();           // 5 cm
  const auto fraction_within = [](const std::vector<double>& v, double x) {
    return static_cast<double>(
               std::count_if(v.begin(), v.end(), [&](double y) { return y <= x; })) /
           static_cast<double>(v.size());
  };
  const double med = median(paint);
  const double within = fraction_within(paint, gsd + res);
  const double gated = fraction_within(all, 10.0 * res);
  // And the whole step: VdtOptimizer::solve from a tracking guess (3 cm, 2 cm, 0.01 rad off).
  VdtOptimizerOptions oo;
  oo.sensor.gate = 10.0 * res;
  oo.min_inliers = 50;
  const LocalizationResult r =
      VdtOptimizer(s.map, oo).solve(frame.observations, truth + Pose2(0.03, -0.02, 0.01));
  std::printf("solve from a tracking guess: %s, error %.3f m, %.4f rad, %d inliers\n",
              to_string(r.status), pose_error(r.pose, truth).head<2>().norm(),
              pose_error(r.pose, truth)[2], r.inliers);
  EXPECT_LT(pose_error(r.pose, truth).head<2>().norm(), 0.1);
  EXPECT_LT(std::abs(pose_error(r.pose, truth)[2]), 0.01);
  // Measured: 2000 edge points, 1247 next to paint; on those the median is 2.7 cm (bound 3.9 cm)
  // and 100 % are within 7.7 cm; 74.5 % of all points are within the 0.5 m gate (the rest: cracks).
  std::printf(
      "edge points %zu, %zu next to paint: median %.4f m (bound %.4f), within %.4f m: "
      "%.1f %%; all points within the gate: %.1f %%\n",
      all.size(), paint.size(), med, 0.5 * gsd + 0.5 * res, gsd + res, 100.0 * within,
      100.0 * gated);
  ASSERT_GE(paint.size(), 500u);
  EXPECT_LT(med, 0.5 * gsd + 0.5 * res);
  EXPECT_GE(within, 0.9);
  EXPECT_GE(gated, 0.6);
}

// ---------------------------------------------------------------------------------------------
// b. The sensor model's cross derivative against finite differences, in 2D and 3D.

template <int Dim>
VdtMap<Dim> blob_map();

template <>
VdtMap<2> blob_map<2>() {  // a ring and a slanted wall, 0.05 m cells
  OccupancyGrid<2> g(Eigen::Vector2i(60, 60), GridFrame<2>(0.05, Eigen::Vector2d::Zero()));
  for (int i = 0; i < 60; ++i) {
    for (int j = 0; j < 60; ++j) {
      const Eigen::Vector2d c = g.cell_center(Eigen::Vector2i(i, j));
      const double r = (c - Eigen::Vector2d(1.4, 1.6)).norm();
      if (std::abs(r - 0.7) < 0.03 || std::abs(c.y() - 0.3 * c.x() - 0.2) < 0.03) {
        g(Eigen::Vector2i(i, j)) = 1;
      }
    }
  }
  return VdtMap<2>::build(g);
}

template <>
VdtMap<3> blob_map<3>() {  // a sphere shell and a tilted plane, 0.1 m cells
  OccupancyGrid<3> g(Eigen::Vector3i(30, 30, 30), GridFrame<3>(0.1, Eigen::Vector3d::Zero()));
  for (int i = 0; i < 30; ++i) {
    for (int j = 0; j < 30; ++j) {
      for (int k = 0; k < 30; ++k) {
        const Eigen::Vector3d c = g.cell_center(Eigen::Vector3i(i, j, k));
        const double r = (c - Eigen::Vector3d(1.5, 1.4, 1.6)).norm();
        if (std::abs(r - 0.8) < 0.06 || std::abs(c.z() - 0.2 * c.x() - 0.4) < 0.06) {
          g(Eigen::Vector3i(i, j, k)) = 1;
        }
      }
    }
  }
  return VdtMap<3>::build(g);
}

template <typename T>
class CrossPointTest : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(CrossPointTest, Dims);

// cross_point = d^2(|d|^2/2)/dX dp: the point derivative of the pose gradient g = d_pose^T d, which
// itself is checked against central differences of |d|^2/2 along the pose tangent.
TYPED_TEST(CrossPointTest, CrossPointIsTheFiniteDifferenceOfThePoseGradient) {
  constexpr int kDim = TypeParam::value;
  using Traits = PoseTraits<kDim>;
  using Vector = typename Traits::Vector;
  using Tangent = typename Traits::Tangent;
  constexpr int kDoF = Traits::kDoF;
  const VdtMap<kDim> map = blob_map<kDim>();
  VdtSensorModelOptions so;
  so.gate_mode = GateMode::kNone;
  const VdtSensorModelT<kDim> model(map, so);
  Tangent xi;
  for (int k = 0; k < kDoF; ++k) xi[k] = 0.03 * (k % 2 == 0 ? 1.0 : -1.0) * (1.0 + 0.3 * k);
  const auto pose = Traits::plus(Traits::identity(), xi);
  const auto r = Traits::rotation(pose);
  const Vector t = Traits::translation(pose);
  const auto gradient = [&](const typename Traits::Pose& x, const Vector& p) {
    const auto b = model.disparity(x, p, Vector::Zero());
    return Tangent(b.d_pose.transpose() * b.d);
  };
  const auto cost = [&](const typename Traits::Pose& x, const Vector& p) {
    return 0.5 * model.disparity(x, p, Vector::Zero()).d.squaredNorm();
  };
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> inside(0.6, 2.3);
  std::normal_distribution<double> gauss;
  for (int trial = 0; trial < 40; ++trial) {
    Vector w, u;
    for (int d = 0; d < kDim; ++d) w[d] = inside(rng);
    for (int d = 0; d < kDim; ++d) u[d] = gauss(rng);
    u.normalize();
    const Vector p = r.transpose() * (w - t);  // robot-frame point that lands at w
    BeamCurvatureT<kDim> c;
    const auto b = model.disparity(pose, p, u, &c);
    ASSERT_TRUE(b.inside);

    const double hx = 3e-4;  // the pose gradient, by central differences along the tangent
    Tangent g_fd;
    for (int k = 0; k < kDoF; ++k) {
      Tangent e = Tangent::Zero();
      e[k] = hx;
      g_fd[k] = (cost(Traits::plus(pose, e), p) - cost(Traits::plus(pose, -e), p)) / (2.0 * hx);
    }
    const Tangent g = gradient(pose, p);
    EXPECT_LT((g - g_fd).norm(), 2e-3 * std::max(1.0, g.norm())) << "trial " << trial;

    const double hp = 3e-4;  // its derivative along the point
    Eigen::Matrix<double, kDoF, kDim> cross_fd;
    for (int d = 0; d < kDim; ++d) {
      Vector e = Vector::Zero();
      e[d] = hp;
      cross_fd.col(d) = (gradient(pose, p + e) - gradient(pose, p - e)) / (2.0 * hp);
    }
    EXPECT_LT((c.cross_point - cross_fd).norm(), 2e-3 * std::max(1.0, cross_fd.norm()))
        << "trial " << trial << "\nanalytic\n"
        << c.cross_point << "\nfinite differences\n"
        << cross_fd;
    // d_point = dd/dp, by central differences of d.
    Eigen::Matrix<double, kDim, kDim> d_point_fd;
    for (int d = 0; d < kDim; ++d) {
      Vector e = Vector::Zero();
      e[d] = hp;
      d_point_fd.col(d) =
          (model.disparity(pose, p + e, u).d - model.disparity(pose, p - e, u).d) / (2.0 * hp);
    }
    EXPECT_LT((b.d_point - d_point_fd).norm(), 2e-3 * std::max(1.0, d_point_fd.norm()))
        << "trial " << trial << "\nanalytic\n"
        << b.d_point << "\nfinite differences\n"
        << d_point_fd;
    // The range derivative is the point derivative along the beam: dp/dr = u.
    EXPECT_LT((c.cross - c.cross_point * u).norm(), 1e-12 * std::max(1.0, c.cross.norm()));
    EXPECT_LT((b.d_range - b.d_point * u).norm(), 1e-12 * std::max(1.0, b.d_range.norm()));
  }
}

// ---------------------------------------------------------------------------------------------
// c. Monte Carlo NEES with the errors every point of a frame shares.

/// Wide painted bands (0.6 m) on a 0.05 m grid, two along x and two along y, apart from each other:
/// along a band's long edges, away from its ends, DT_v is exactly linear (the spline reproduces
/// it), so points on those edges have zero disparity at the true pose and the map adds no error.
struct BandMap {
  OccupancyGrid<2> grid;
  VdtMap2 map;
  std::vector<Eigen::Vector2d> edge_points;  ///< world points on boundary rows, 0.25 m apart
};

const BandMap& band_map() {
  static const BandMap m = [] {
    BandMap b;
    b.grid = OccupancyGrid<2>(Eigen::Vector2i(600, 480),
                              GridFrame<2>(0.05, Eigen::Vector2d(-15.0, -12.0)));
    const auto band = [&](int i0, int i1, int j0, int j1) {
      for (int i = i0; i <= i1; ++i) {
        for (int j = j0; j <= j1; ++j) b.grid(Eigen::Vector2i(i, j)) = 1;
      }
      const Eigen::Vector2d lo = b.grid.cell_center(Eigen::Vector2i(i0, j0));
      const Eigen::Vector2d hi = b.grid.cell_center(Eigen::Vector2i(i1, j1));
      const bool along_x = (i1 - i0) > (j1 - j0);
      for (int side = 0; side < 2; ++side) {
        for (double s = 0.6;; s += 0.25) {
          if (along_x) {
            if (lo.x() + s > hi.x() - 0.6) break;
            b.edge_points.emplace_back(lo.x() + s, side == 0 ? lo.y() : hi.y());
          } else {
            if (lo.y() + s > hi.y() - 0.6) break;
            b.edge_points.emplace_back(side == 0 ? lo.x() : hi.x(), lo.y() + s);
          }
        }
      }
    };
    band(120, 480, 300, 311);  // x -9..9, y 3.0..3.6
    band(120, 480, 160, 171);  // x -9..9, y -4.0..-3.4
    band(180, 191, 190, 280);  // x -6..-5.4, y -2.5..2.0
    band(380, 391, 190, 280);  // x 4..4.6, y -2.5..2.0
    b.map = VdtMap2::build(marking_boundaries(b.grid));
    return b;
  }();
  return m;
}

/// The distorted pixel that sees level-frame ground point q at attitude `a` (the inverse of
/// project_to_ground); false when q is behind the camera or outside the image.
bool pixel_of(const PinholeCamera& camera, const UavRig& rig, const AttitudeReading& a,
              const Eigen::Vector2d& q, Eigen::Vector2d* pixel) {
  const double h = altitude(a, rig);
  const Eigen::Vector3d body = level_from_body(a.roll, a.pitch).transpose() *
                               (Eigen::Vector3d(q.x(), q.y(), 0.0) - Eigen::Vector3d(0, 0, h));
  const Eigen::Vector3d cam = rig.body_from_camera.inverse() * body;
  if (cam.z() <= 0.0) return false;
  *pixel = camera.distort(cam.head<2>() / cam.z());
  return pixel->x() >= 8.0 && pixel->y() >= 8.0 && pixel->x() <= camera.width() - 9.0 &&
         pixel->y() <= camera.height() - 9.0;
}

TEST(UavLocalization, CovariancesWithTheSharedAttitudeErrorsPassMonteCarloNees) {
  const BandMap& bm = band_map();
  const PinholeCamera camera(distorted_camera());
  const UavRig rig;
  const GroundProjectionNoise noise;  // 0.5 px, 0.2 deg roll and pitch, 5 cm laser
  const double h = 15.0;
  const AttitudeReading truth_att = exact_reading(3.0 * kDeg, -2.0 * kDeg, h);
  const Pose2 truth(0.3, -0.2, 0.3);

  // Edge pixels that see the band edges at the true pose and attitude.
  std::vector<Eigen::Vector2d> pixels;
  for (const Eigen::Vector2d& w : bm.edge_points) {
    ASSERT_LT(bm.map.value(w).norm(), 1e-6);  // exactly on a boundary row
    const Eigen::Vector2d q = transform_point(between(truth, Pose2::Zero()), w);
    Eigen::Vector2d px;
    if (!pixel_of(camera, rig, truth_att, q, &px)) continue;
    const GroundPoint gp =
        project_to_ground(camera.undistort({px}).front(), truth_att, rig);  // round trip
    ASSERT_TRUE(gp.valid);
    ASSERT_LT((gp.p - q).norm(), 1e-6);
    pixels.push_back(px);
  }
  ASSERT_GE(pixels.size(), 200u);

  const double res = bm.map.resolution();
  VdtOptimizerOptions oo;
  oo.sensor.gate = 10.0 * res;
  // The bands' edges are exact in the map: a floor far below the 1.4 cm of the pixel noise
  // (it keeps the rank-one disparity covariance of a straight edge invertible for the EKF).
  oo.sensor.map_sigma = 0.002;
  oo.min_inliers = 50;
  const VdtOptimizer optimizer(bm.map, oo);
  VdtEkfOptions eo;
  eo.sensor = oo.sensor;
  eo.min_inliers = 50;
  eo.motion = MotionModelKind::kOdometryIncrement;
  eo.search.enabled = false;  // the update itself, from the truth
  VdtEkfLocalizer ekf(bm.map, eo);
  const Eigen::Matrix3d broad = Eigen::Vector3d(100.0, 100.0, 10.0).asDiagonal();

  std::mt19937_64 rng(2024);
  std::normal_distribution<double> n01;
  const int trials = 300;
  std::vector<double> opt_shared, opt_independent, ekf_shared, ekf_independent;
  int ekf_failed = 0, ekf_independent_failed = 0;
  for (int k = 0; k < trials; ++k) {
    AttitudeReading a = truth_att;  // what the IMU and the laser report: theta ~ N(0, cov)
    a.roll += noise.sigma_roll * n01(rng);
    a.pitch += noise.sigma_pitch * n01(rng);
    a.laser_range += noise.sigma_laser_range * n01(rng);
    std::vector<Eigen::Vector2d> noisy = pixels;
    for (Eigen::Vector2d& px : noisy) px += noise.sigma_pixel * Eigen::Vector2d(n01(rng), n01(rng));
    const ObservationSet2 obs = ground_observations(noisy, camera, rig, a, noise);
    ASSERT_EQ(obs.size(), pixels.size());
    ASSERT_EQ(obs.num_shared(), 3);
    ObservationSet2 independent = obs;  // the same points, the shared term dropped
    independent.shared_jacobians.clear();

    const LocalizationResult r = optimizer.solve(obs, truth);
    ASSERT_EQ(r.status, LocalizationStatus::kConverged);
    ASSERT_TRUE(r.has_covariance);
    opt_shared.push_back(eval::nees(r.pose, truth, r.covariance));
    const LocalizationResult ri = optimizer.solve(independent, truth);
    ASSERT_TRUE(ri.has_covariance);
    opt_independent.push_back(eval::nees(ri.pose, truth, ri.covariance));

    ekf.reset(truth, broad);
    const LocalizationResult e = ekf.update(OdometryStep{}, obs);
    if (e.status == LocalizationStatus::kConverged) {
      ekf_shared.push_back(eval::nees(e.pose, truth, e.covariance));
    } else {
      ++ekf_failed;
    }
    ekf.reset(truth, broad);
    const LocalizationResult ei = ekf.update(OdometryStep{}, independent);
    if (ei.status == LocalizationStatus::kConverged) {
      ekf_independent.push_back(eval::nees(ei.pose, truth, ei.covariance));
    } else {
      ++ekf_independent_failed;
    }
  }
  const eval::AneesResult a_opt = eval::anees(opt_shared, 3, 0.99);
  const eval::AneesResult a_opt_i = eval::anees(opt_independent, 3, 0.99);
  const eval::AneesResult a_ekf = eval::anees(ekf_shared, 3, 0.99);
  const eval::AneesResult a_ekf_i = eval::anees(ekf_independent, 3, 0.99);
  // Measured (259 points, 300 trials, 99 % interval [2.65, 3.38]): vdt-opt 2.86, without the
  // shared term 3911; vdt-ekf 2.88 with none of the 300 updates refused, without 3923.
  std::printf(
      "%zu points; ANEES in [%.2f, %.2f]: vdt-opt %.2f (without shared %.1f), vdt-ekf %.2f "
      "(without shared %.1f)\n",
      pixels.size(), a_opt.interval.lower, a_opt.interval.upper, a_opt.anees, a_opt_i.anees,
      a_ekf.anees, a_ekf_i.anees);
  std::printf("vdt-ekf updates refused: %d with the shared errors, %d without\n", ekf_failed,
              ekf_independent_failed);
  // Every update starts at the truth with an uninformative prior: none may be refused.
  EXPECT_EQ(ekf_failed, 0);
  EXPECT_EQ(ekf_independent_failed, 0);
  EXPECT_EQ(a_opt.count, static_cast<std::size_t>(trials));
  EXPECT_TRUE(a_opt.consistent) << a_opt.anees;
  EXPECT_TRUE(a_ekf.consistent) << a_ekf.anees;
  // Without the common-mode term the covariance is that of independent per-point errors, which
  // average out over the points: far too small.
  EXPECT_GT(a_opt_i.anees, 10.0 * a_opt_i.interval.upper);
  EXPECT_GT(a_ekf_i.anees, 10.0 * a_ekf_i.interval.upper);
}

// ---------------------------------------------------------------------------------------------
// d. No markings in view.

TEST(UavLocalization, FramesWithoutMarkingsAreTooFewObservationsAndKeepThePrediction) {
  const BandMap& bm = band_map();
  const double res = bm.map.resolution();
  VdtOptimizationLocalizer opt(bm.map, example_optimizer(res, 15.0));
  VdtEkfLocalizer ekf(bm.map, example_ekf(res, 15.0));
  // 300 points (more than min_inliers = 50) on grass: in the map's corner, over 1 m from any band.
  const Pose2 start(11.0, -9.0, 0.2);
  OdometryStep odo;
  odo.dt = 0.1;
  odo.delta = Pose2(0.4, 0.02, 0.01);
  const Pose2 predicted = compose(start, odo.delta);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ux(10.0, 14.5), uy(-11.5, -8.0);
  ObservationSet2 grass;
  for (std::size_t i = 0; i < 300; ++i) {
    const Eigen::Vector2d w(ux(rng), uy(rng));
    ASSERT_GT(bm.map.value(w).norm(), 1.0);
    grass.add_point(transform_point(between(predicted, Pose2::Zero()), w),
                    Eigen::Matrix2d::Identity() * 1e-4, i);
  }
  for (Localizer2D* l : {static_cast<Localizer2D*>(&opt), static_cast<Localizer2D*>(&ekf)}) {
    l->reset(start, Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal());
    const LocalizationResult r = l->update(odo, grass);
    EXPECT_EQ(r.status, LocalizationStatus::kTooFewObservations) << l->name();
    EXPECT_LT(pose_error(r.pose, predicted).norm(), 1e-9) << l->name();
  }
}

TEST(UavLocalization, RenderedFrameOverPlainGrassIsTooFewObservations) {
  const Scene& s = runway();
  const CameraCalibration cal = distorted_camera();
  const UavRig rig;
  const GroundRenderer renderer(cal, rig);
  const UavCameraFrontEnd front(cal, rig);
  // Beyond the textured grass: the scene's plain background fills the view.
  const Pose2 start(0.0, s.scene.runway.max().y() + 30.0, 0.5);
  std::mt19937_64 rng(5);
  const cv::Mat image = renderer.render(
      s.scene.texture, body_pose(start[0], start[1], 15.0, 0.02, -0.01, start[2]), {}, rng);
  const CameraFrame frame = front.observe(image, exact_reading(0.02, -0.01, 15.0));
  EXPECT_TRUE(frame.rejected.empty());
  EXPECT_LT(frame.observations.size(), 50u);
  const double res = s.map.resolution();
  VdtOptimizationLocalizer opt(s.map, example_optimizer(res, 15.0));
  VdtEkfLocalizer ekf(s.map, example_ekf(res, 15.0));
  OdometryStep odo;
  odo.dt = 0.1;
  odo.delta = Pose2(0.4, 0.0, 0.0);
  for (Localizer2D* l : {static_cast<Localizer2D*>(&opt), static_cast<Localizer2D*>(&ekf)}) {
    l->reset(start, Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal());
    const LocalizationResult r = l->update(odo, frame.observations);
    EXPECT_EQ(r.status, LocalizationStatus::kTooFewObservations) << l->name();
    EXPECT_LT(pose_error(r.pose, compose(start, odo.delta)).norm(), 1e-9) << l->name();
  }
}

// ---------------------------------------------------------------------------------------------
// e. Re-acquisition after the markings leave the view while the odometry drifts.

/// Runs the outage scenario below through the optimizer (`ekf` false) or the EKF.
void check_reacquisition(bool use_ekf) {
  const Scene& s = runway();
  const CameraCalibration cal = distorted_camera();
  const UavRig rig;
  const GroundRenderer renderer(cal, rig);
  UavCameraOptions co;  // the example's sensor noise (the defaults): 0.2 deg, 5 cm
  const UavCameraFrontEnd front(cal, rig, co);
  GroundTexture grass;  // plain grass: the background everywhere
  grass.image = cv::Mat(2, 2, CV_8UC1, cv::Scalar(96));
  grass.origin = Eigen::Vector2d(1e4, 1e4);
  grass.background = 96.0;

  const double h = 15.0, res = s.map.resolution();
  VdtOptimizationLocalizer opt(s.map, example_optimizer(res, h));
  VdtEkfLocalizer ekf(s.map, example_ekf(res, h));
  std::vector<Localizer2D*> methods{use_ekf ? static_cast<Localizer2D*>(&ekf) : &opt};

  // Along the road at 4 m/s, 10 Hz (4 centreline points per frame): 25 frames with the markings
  // (2.5 s: from the 0.5 m start prior the EKF needs ~2 s to settle; with 15 it was still 0.30 m
  // off when the outage began, so the test did not test re-acquisition), 40 without (a 4 s camera
  // outage), 20 with them again. The odometry over-reports the distance
  // by 6 %: the prediction is ~1 m off when the markings return.
  const int before = 25, gap = 40, after = 20, frames = before + gap + after;
  const double bias = 1.06;
  std::vector<Pose2> truth;
  for (int k = 0; k < frames; ++k) truth.push_back(road_pose(s.scene.centreline, 400 + 4 * k));
  std::mt19937_64 rng(17);
  std::normal_distribution<double> n01;
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.25, 0.25, 0.01).asDiagonal();
  for (Localizer2D* l : methods) l->reset(truth[0], p0);
  std::vector<std::vector<double>> err(methods.size());
  for (int k = 0; k < frames; ++k) {
    const bool features = k < before || k >= before + gap;
    const double roll = 2.0 * kDeg * std::sin(0.3 * k), pitch = -1.5 * kDeg * std::cos(0.2 * k);
    const cv::Mat image =
        renderer.render(features ? s.scene.texture : grass,
                        body_pose(truth[k][0], truth[k][1], h, roll, pitch, truth[k][2]), {}, rng);
    AttitudeReading reading = exact_reading(roll, pitch, h);
    reading.roll += co.noise.sigma_roll * n01(rng);
    reading.pitch += co.noise.sigma_pitch * n01(rng);
    reading.laser_range += co.noise.sigma_laser_range * n01(rng);
    const CameraFrame frame = front.observe(image, reading);
    if (!features) {
      ASSERT_LT(frame.observations.size(), 50u);
    }
    OdometryStep odo;
    odo.dt = 0.1;
    if (k > 0) {
      odo.delta = between(truth[k - 1], truth[k]);
      odo.delta.head<2>() *= bias;
    }
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const LocalizationResult r = methods[m]->update(odo, frame.observations);
      err[m].push_back(pose_error(r.pose, truth[k]).head<2>().norm());
    }
  }
  for (std::size_t m = 0; m < methods.size(); ++m) {
    const double before_error = err[m][before - 1];
    const double gap_error = err[m][before + gap - 1];
    int recovered = -1;
    for (int j = before + gap; j < frames; ++j) {
      if (err[m][j] < 0.2) {
        recovered = j - (before + gap);
        break;
      }
    }
    for (int j = before + gap; j < frames; ++j) std::printf(" %.2f", err[m][j]);
    std::printf("\n");
    // Measured: vdt-opt 0.067 m before the gap, 0.96 m at its end, below 0.2 m 2 frames after the
    // markings return; vdt-ekf 0.058 m, 0.95 m, on the first frame back.
    std::printf("%s: error %.3f m before the gap, %.3f m at its end, below 0.2 m %d frames after\n",
                methods[m]->name().c_str(), before_error, gap_error, recovered);
    EXPECT_LT(before_error, 0.3) << methods[m]->name();
    EXPECT_GT(gap_error, 0.7) << methods[m]->name() << ": the test needs a drifted prediction";
    EXPECT_GE(recovered, 0) << methods[m]->name();
    EXPECT_LT(recovered, 10) << methods[m]->name();
    for (int j = before + gap + std::max(recovered, 0) + 1; j < frames; ++j) {
      EXPECT_LT(err[m][j], 0.3) << methods[m]->name() << " frame " << j;
    }
  }
}

TEST(UavLocalization, ReacquiresWithinOneSecondWhenTheMarkingsReturn) {
  check_reacquisition(false);
}

TEST(UavLocalization, EkfReacquiresWithinOneSecondWhenTheMarkingsReturn) {
  check_reacquisition(true);
}

// ---------------------------------------------------------------------------------------------
// f. Bad input.

TEST(UavLocalization, WrongImageSizeThrowsWithTheExpectedSize) {
  const UavCameraFrontEnd front(distorted_camera(), UavRig{});
  const cv::Mat image(240, 320, CV_8UC1, cv::Scalar(100));
  try {
    (void)front.observe(image, exact_reading(0.0, 0.0, 15.0));
    FAIL() << "no exception";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("640x480"), std::string::npos) << what;
    EXPECT_NE(what.find("320x240"), std::string::npos) << what;
  }
}

TEST(UavLocalization, UnusableAttitudeGivesNoObservationAndThePrediction) {
  const Scene& s = runway();
  const CameraCalibration cal = distorted_camera();
  const UavRig rig;
  const GroundRenderer renderer(cal, rig);
  const UavCameraFrontEnd front(cal, rig);
  const Pose2 truth = road_pose(s.scene.centreline, 100);
  std::mt19937_64 rng(9);
  const cv::Mat image = renderer.render(
      s.scene.texture, body_pose(truth[0], truth[1], 15.0, 0.0, 0.0, truth[2]), {}, rng);
  struct Case {
    AttitudeReading reading;
    const char* says;
  };
  const Case cases[] = {
      {{std::nan(""), 0.0, 15.0}, "roll"},
      {{0.0, 0.0, -1.5}, "laser range"},
  };
  const double res = s.map.resolution();
  for (const Case& c : cases) {
    const CameraFrame frame = front.observe(image, c.reading);
    EXPECT_EQ(frame.observations.size(), 0u) << c.says;
    EXPECT_NE(frame.rejected.find(c.says), std::string::npos) << frame.rejected;
    EXPECT_FALSE(frame.edges.empty());  // the image itself is fine
    VdtOptimizationLocalizer opt(s.map, example_optimizer(res, 15.0));
    VdtEkfLocalizer ekf(s.map, example_ekf(res, 15.0));
    const Pose2 start = compose(truth, Pose2(-0.4, 0.0, 0.0));
    OdometryStep odo;
    odo.dt = 0.1;
    odo.delta = Pose2(0.4, 0.0, 0.0);
    for (Localizer2D* l : {static_cast<Localizer2D*>(&opt), static_cast<Localizer2D*>(&ekf)}) {
      l->reset(start, Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal());
      const LocalizationResult r = l->update(odo, frame.observations);
      EXPECT_EQ(r.status, LocalizationStatus::kTooFewObservations) << l->name() << " " << c.says;
      EXPECT_TRUE(r.pose.allFinite());
      EXPECT_LT(pose_error(r.pose, compose(start, odo.delta)).norm(), 1e-9) << l->name();
    }
  }
}

}  // namespace
}  // namespace vdtnav::uav_camera
