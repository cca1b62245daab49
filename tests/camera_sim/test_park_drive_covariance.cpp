// The PMD study's filter on the first frames of a generated drive (examples/pmd_rgbd's settings,
// seed 4): the covariance the VDT EKF reports, its own plus the map term of the 2 m squares,
// stays bounded on every frame. The frames whose boundaries run along the track observe that
// direction barely; a map term from the scan's information alone reported 2 sigma of 10 km there
// (frame 28) and up to 4e8 m later in the drive, and a bearing fused against it moved the
// estimate 3 m.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include <Eigen/Eigenvalues>

#include "vdtnav/camera_sim/landmark_detections.hpp"
#include "vdtnav/camera_sim/park_renderer.hpp"
#include "vdtnav/camera_sim/park_scene.hpp"
#include "vdtnav/camera_sim/scooter_drive.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/rgbd_ground/ground_boundaries.hpp"

namespace vdtnav::rgbd_ground {
namespace {

TEST(ParkDrive, TheReportedCovarianceStaysBoundedWhereBoundariesRunAlongTheTrack) {
  const std::uint64_t seed = 4;
  ParkSceneOptions po;
  po.seed = seed;
  const ParkScene scene = generate_park(po);
  const double res = 0.05;
  const VdtMap2 map = VdtMap2::build(scene.boundary_map(res));
  ScooterDriveOptions dopt;
  dopt.seed = seed;
  const ScooterDrive drive = simulate_scooter_drive(scene, dopt);
  const camera::CameraCalibration calibration = default_rgbd_calibration();
  const Eigen::Isometry3d mount = default_rear_camera();
  GroundBoundaryOptions bo;
  bo.noise.sigma_pixel = bo.blur_sigma;
  const GroundBoundaryExtractor extractor(camera::PinholeCamera(calibration), mount, bo);
  const ParkRenderer renderer(scene, calibration, mount);
  VdtEkfOptions eo;  // examples/pmd_rgbd/filter_run.cpp
  eo.motion = MotionModelKind::kOdometryIncrement;
  eo.noise = drive_odometry_noise(dopt);
  eo.sensor.gate = 5.0 * res;
  eo.sensor.map_sigma = 0.5 * res;
  eo.sensor.map_correlation_length = 2.0;
  eo.sensor.map_pose_sigma = 0.0;
  eo.min_inliers = 20;
  VdtEkfLocalizer ekf(map, eo);
  ekf.reset(drive.truth[0], Eigen::Vector3d(0.01, 0.01, 0.0004).asDiagonal());
  std::mt19937 rng(static_cast<std::uint32_t>(seed * 7919 + 17));
  const RenderOptions ro = RenderOptions::localization_day();
  double worst = 0.0;
  for (std::size_t k = 0; k < 40; ++k) {
    const RgbdFrame frame = renderer.render(drive.truth[k], ro, rng);
    (void)detect_landmarks(scene, drive.truth[k], DetectionOptions{}, rng);  // the study's draws
    const LocalizationResult r = ekf.update(k == 0 ? OdometryStep{} : drive.odometry[k],
                                            extractor.observations(extractor.extract(frame)));
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(
        ekf.reported_covariance().topLeftCorner<2, 2>());
    const double sd = std::sqrt(es.eigenvalues()[1]);
    worst = std::max(worst, sd);
    // Bounded by what the drive can have lost: the start's 10 cm and 40 odometry steps.
    EXPECT_LT(sd, 0.5) << "frame " << k;
    EXPECT_LT(pose_error(r.pose, drive.truth[k]).head<2>().norm(), 0.3) << "frame " << k;
  }
  std::printf("largest reported sigma over 40 frames: %.3f m\n", worst);
}

}  // namespace
}  // namespace vdtnav::rgbd_ground
