// The PMD study's run: every frame of the drive rendered from the true pose, its ground boundaries
// extracted and back-projected, landmark bearings detected, and the four filters (vdt-ekf,
// vdt-ekf+bearings, bearings, odometry) run side by side on them.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "pmd_study.hpp"
#include "vdtnav/camera_sim/landmark_detections.hpp"
#include "vdtnav/camera_sim/park_renderer.hpp"
#include "vdtnav/estimation/bearing_update.hpp"
#include "vdtnav/estimation/motion_model.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/rgbd_ground/ground_boundaries.hpp"
#include "vdtnav/rgbd_ground/rgbd_frame.hpp"

namespace pmd_study {

using namespace vdtnav;
using namespace vdtnav::rgbd_ground;
using Clock = std::chrono::steady_clock;

FilterRun run_filters(const Scenario& sc, double correlation_length, bool schmidt,
                      double correction_gate, std::uint64_t seed, bool verbose) {
  const ParkScene& scene = sc.scene;
  const double resolution = sc.resolution;
  const VdtMap2& map = sc.map;
  const ScooterDriveOptions& dopt = sc.dopt;
  const ScooterDrive& drive = sc.drive;
  const std::size_t n = sc.n;

  // ------------------------------------------------------------------ front end and filters
  const camera::CameraCalibration calibration = default_rgbd_calibration();
  const Eigen::Isometry3d camera_to_robot = default_rear_camera();
  // Canny on the blurred image places an edge within the blur's sigma: that is the pixel noise
  // of a boundary point (the sensor's depth noise stays the front end's default, Kinect-class).
  GroundBoundaryOptions bo;
  bo.noise.sigma_pixel = bo.blur_sigma;
  const GroundBoundaryExtractor extractor(camera::PinholeCamera(calibration), camera_to_robot, bo);
  const ParkRenderer renderer(scene, calibration, camera_to_robot);
  const std::vector<Landmark2> landmarks = park_landmarks(scene);

  MotionNoise odo = drive_odometry_noise(dopt);
  VdtEkfOptions eo;
  eo.motion = MotionModelKind::kOdometryIncrement;
  eo.noise = odo;
  // The map from the surfaces: a boundary is a band of two cells whose middle it crosses
  // anywhere within +-resolution/2 (the map floor), an error shared along the boundary (map
  // errors correlated over 2 m, as for maps drawn from scans; the polygons themselves are exact:
  // map_pose_sigma 0); the gate is 5 cells.
  eo.sensor.gate = 5.0 * resolution;
  eo.sensor.map_sigma = 0.5 * resolution;
  eo.sensor.map_correlation_length = correlation_length;
  eo.schmidt_map_errors = schmidt;
  eo.sensor.map_pose_sigma = 0.0;
  eo.min_inliers = 20;
  // A frame registered to the wrong stretch of a boundary jumps along it by tens of centimetres
  // while its covariance shrinks (issue 35): such a correction, implausible under the prior, is
  // refused (VdtEkfOptions::correction_gate, --correction-gate).
  eo.correction_gate = correction_gate;
  VdtEkfLocalizer vdt(map, eo, "vdt-ekf");
  VdtEkfLocalizer fused(map, eo, "vdt-ekf+bearings");
  // The start: within 10 cm and 0.02 rad, as a GNSS fix and a compass would give it.
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.01, 0.01, 0.0004).asDiagonal();
  for (VdtEkfLocalizer* f : {&vdt, &fused}) f->reset(drive.truth[0], p0);
  // The landmark-only filter and dead reckoning need no map: the same prediction on (x, P).
  Pose2 landmark_x = drive.truth[0], dead = drive.truth[0];
  Eigen::Matrix3d landmark_p = p0, dead_p = p0;
  std::vector<Trace> traces{{"vdt-ekf", {}, {}, 0.0, true, {}, 0},
                            {"vdt-ekf+bearings", {}, {}, 0.0, true, {}, 0},
                            {"bearings", {}, {}, 0.0, false, {}, 0},
                            {"odometry", {}, {}, 0.0, false, {}, 0}};

  // ------------------------------------------------------------------ the run
  std::mt19937 rng(static_cast<std::uint32_t>(seed * 7919 + 17));
  RenderOptions ro = RenderOptions::localization_day();
  DetectionOptions det;
  BearingUpdateOptions bearing_options;
  double front_ms = 0.0;
  const std::size_t shown = n / 3;
  cv::Mat shown_colour;
  GroundBoundaries shown_boundaries;
  std::printf("[run] rendering, extracting and filtering %zu frames\n", n);
  for (std::size_t k = 0; k < n; ++k) {
    const Pose2& truth = drive.truth[k];
    const RgbdFrame frame = renderer.render(truth, ro, rng);
    const auto t0 = Clock::now();
    const GroundBoundaries b = extractor.extract(frame);
    const ScanPoints obs = extractor.observations(b);
    const double frame_front_ms =
        std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    front_ms += frame_front_ms;
    if (k == shown) {
      shown_colour = frame.colour;
      shown_boundaries = b;
    }
    const std::vector<BearingDetection> z = detect_landmarks(scene, truth, det, rng);
    const OdometryStep step = k == 0 ? OdometryStep{} : drive.odometry[k];
    const auto timed = [&](Trace& t, auto&& f) {
      const auto t1 = Clock::now();
      f();
      const double filter_ms = std::chrono::duration<double, std::milli>(Clock::now() - t1).count();
      t.ms += filter_ms;
      t.frame_ms.push_back(filter_ms + (t.uses_frames ? frame_front_ms : 0.0));
    };
    timed(traces[0], [&] {
      const LocalizationResult r = vdt.update(step, obs);
      traces[0].refused += r.status == LocalizationStatus::kRefused;
      traces[0].estimate.push_back(r.pose);
      traces[0].covariance.push_back(r.covariance);
    });
    timed(traces[1], [&] {
      traces[1].refused += fused.update(step, obs).status == LocalizationStatus::kRefused;
      (void)fused.update_bearings(z, landmarks, bearing_options);
      traces[1].estimate.push_back(fused.pose());
      traces[1].covariance.push_back(fused.reported_covariance());
    });
    timed(traces[2], [&] {
      if (k > 0) ekf_predict(eo.motion, eo.noise, step, landmark_x, landmark_p);
      (void)ekf_bearing_update(z, landmarks, bearing_options, landmark_x, landmark_p);
      traces[2].estimate.push_back(landmark_x);
      traces[2].covariance.push_back(landmark_p);
    });
    timed(traces[3], [&] {
      if (k > 0) ekf_predict(eo.motion, eo.noise, step, dead, dead_p);
      traces[3].estimate.push_back(dead);
      traces[3].covariance.push_back(dead_p);
    });
    if (verbose) {
      std::printf("frame %zu: %zu points (%d pruned), %zu detections", k, obs.size(), b.pruned,
                  z.size());
      for (const Trace& t : traces) {
        const Eigen::Vector3d e = pose_error(t.estimate[k], truth);
        std::printf(" | %s (%.3f %.3f %.4f) 2sd (%.3f %.3f %.4f)", t.name.c_str(), e[0], e[1], e[2],
                    2.0 * std::sqrt(t.covariance[k](0, 0)), 2.0 * std::sqrt(t.covariance[k](1, 1)),
                    2.0 * std::sqrt(t.covariance[k](2, 2)));
      }
      std::printf("\n");
    }
    if ((k + 1) % 200 == 0 || k + 1 == n) {
      std::printf("  frame %zu/%zu  points %zu  vdt-ekf error %.3f m\n", k + 1, n, obs.size(),
                  pose_error(traces[0].estimate[k], truth).head<2>().norm());
      std::fflush(stdout);
    }
  }
  front_ms /= static_cast<double>(n);
  for (const Trace& t : traces)
    if (t.uses_frames)
      std::printf(
          "  %s: %d of %zu frames' boundary updates refused (map does not explain the "
          "frame, or the correction gate)\n",
          t.name.c_str(), t.refused, n);
  return FilterRun{std::move(traces), front_ms, landmarks, shown, shown_colour, shown_boundaries};
}

}  // namespace pmd_study
