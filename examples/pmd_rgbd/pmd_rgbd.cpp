// A personal mobility device localized outdoors with a rear RGB-D camera (thesis 3.4.5, Dataset
// 5; Figs. 3.19-3.24): a scooter drives along the paths of a generated park; every frame is
// rendered from the true pose (textured grass, pavement and gravel, obstacles standing on the
// ground and their shadows, depth noise and holes, and a light that differs from the mapping
// day), the boundaries between ground surfaces are extracted without a neural network and
// back-projected with depth, and four filters run side by side on the same frames:
//   vdt-ekf            the VDT EKF with the boundary points (3.23-3.24, corrected per SPEC),
//   vdt-ekf+bearings   the same filter also fed bearings to known landmarks (lamp posts, signs),
//   bearings           the landmark-only EKF (the framework the thesis augmented),
//   odometry           dead reckoning.
//
//   vdtnav_pmd_rgbd [--out DIR] [--seed N] [--frames N] [--verbose]
//                   [--map-correlation-length M] [--schmidt-map-errors]
//   vdtnav_pmd_rgbd --kinect FRAMES_DIR [--calibration FILE] [--out DIR]
//
// Writes DIR/table.csv (method,frames,pos_rmse_m,yaw_rmse_rad,anees,anees_lo,anees_hi,
// within_2sigma_pct,ms_per_frame), table.md, errors.png (Fig. 3.23: errors with +-2 sigma),
// trajectories.png (Fig. 3.24) and frame.png (one frame with its kept and pruned boundaries).
// With --kinect, instead: relative localization between recorded RGB-D frames
// (color/{1..5}.png, depth/{1..5}.pgm in mm, pose.txt camera-to-world "tx ty tz qx qy qz qw"):
// each frame's boundary points on a VDT map of the other frames' points, drawn through the given
// poses on the fitted floor, reported against the given poses in DIR/kinect_relative.csv.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "vdtnav/estimation/bearing_update.hpp"
#include "vdtnav/estimation/motion_model.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/io/point_set_map.hpp"
#include "vdtnav/rgbd_ground/camera_mount.hpp"
#include "vdtnav/rgbd_ground/ground_boundaries.hpp"
#include "vdtnav/rgbd_ground/ground_plane.hpp"
#include "vdtnav/rgbd_ground/landmark_detections.hpp"
#include "vdtnav/rgbd_ground/park_renderer.hpp"
#include "vdtnav/rgbd_ground/park_scene.hpp"
#include "vdtnav/rgbd_ground/rgbd_frame.hpp"
#include "vdtnav/rgbd_ground/scooter_drive.hpp"
#include "vdtnav/viz/viz.hpp"

namespace {

using namespace vdtnav;
using namespace vdtnav::rgbd_ground;
using Clock = std::chrono::steady_clock;

/// One filter's run over the drive.
struct Trace {
  std::string name;
  std::vector<Pose2> estimate;
  std::vector<Eigen::Matrix3d> covariance;
  double ms = 0.0;  // filter time over all frames (front end excluded)
  bool uses_frames = false;
};

double rms(const std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s / static_cast<double>(v.size()));
}

viz::RgbImage to_rgb(const cv::Mat& bgr) {
  viz::RgbImage img(bgr.cols, bgr.rows);
  for (int r = 0; r < bgr.rows; ++r)
    for (int c = 0; c < bgr.cols; ++c) {
      const cv::Vec3b v = bgr.at<cv::Vec3b>(r, c);
      std::uint8_t* px = &img.rgb[3 * (static_cast<std::size_t>(r) * bgr.cols + c)];
      px[0] = v[2];
      px[1] = v[1];
      px[2] = v[0];
    }
  return img;
}

/// Relative localization between recorded frames (issue 13, item 5). The camera is hand-held:
/// its robot frame is the floor under it (x forward, y left), with roll, pitch and height from
/// the fitted floor (levelled_extrinsics) and the given pose's yaw and position. Each frame's
/// boundary points are localized by vdt-opt on a 2 cm VDT map of the other frames' points, drawn
/// through the given poses (robot frame of frame 1), from the given pose and from 4 cm, 3 cm and
/// 1 degree off; the errors are against the given poses (a reference with centimetres of error of
/// its own: 3-10 cm of depth disagreement between frames warped through them).
/// `calibration`: an OpenCV or ROS calibration file; empty: the Kinect v1 intrinsics the data's
/// README gives for ../shared/data/vision/rgbd-kinect (no distortion).
int kinect_study(const std::string& dir, const std::string& calibration, const std::string& out) {
  uav_camera::CameraCalibration cal;
  if (calibration.empty()) {
    cal.width = 640;
    cal.height = 480;
    cal.camera_matrix << 518.0, 0.0, 325.5, 0.0, 519.0, 253.5, 0.0, 0.0, 1.0;
  } else {
    cal = uav_camera::read_calibration(calibration);
  }
  const std::vector<Eigen::Isometry3d> poses = read_camera_poses(dir + "/pose.txt");
  // A hand-held camera ~1.4 m up, looking forward and ~25 degrees down; the fit may move it by
  // up to 0.6 rad and 0.4 m. Indoors a carpet's edges are edges of lightness too.
  const Eigen::Isometry3d nominal =
      tilted_camera(Eigen::Vector3d(0.0, 0.0, 1.4), 0.0, 25.0 * M_PI / 180.0);
  GroundBoundaryOptions o;
  o.plane.max_tilt = 0.6;
  o.use_lightness = true;
  const GroundBoundaryExtractor ex(uav_camera::PinholeCamera(cal), nominal, o);
  std::vector<GroundBoundaries> frames;
  std::vector<Eigen::Isometry3d> robot_in_world;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const std::string n = std::to_string(i + 1);
    frames.push_back(ex.extract(
        read_rgbd_frame(dir + "/color/" + n + ".png", dir + "/depth/" + n + ".pgm", 1000.0)));
    if (!frames.back().plane.found) throw std::runtime_error("frame " + n + ": no floor found");
    robot_in_world.push_back(poses[i] *
                             levelled_extrinsics(nominal, frames.back().plane).inverse());
  }
  std::vector<Pose2> given;  // on the floor, robot frame of frame 1
  for (const Eigen::Isometry3d& t : robot_in_world) {
    const Eigen::Isometry3d r = robot_in_world[0].inverse() * t;
    given.emplace_back(r.translation().x(), r.translation().y(),
                       std::atan2(r.linear()(1, 0), r.linear()(0, 0)));
  }
  std::filesystem::create_directories(out);
  std::ofstream csv(out + "/kinect_relative.csv");
  csv << "frame,points,explained_pct,from_given_m,from_given_deg,from_off_m,from_off_deg\n";
  std::printf("[kinect] %zu frames of %s: each on a 2 cm map of the others' boundaries\n",
              frames.size(), dir.c_str());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    std::vector<Eigen::Vector2d> map_points;
    for (std::size_t j = 0; j < frames.size(); ++j) {
      if (j == i) continue;
      const Eigen::Rotation2Dd rot(given[j][2]);
      for (const BoundaryPoint& b : frames[j].points) {
        map_points.push_back(rot * b.robot + given[j].head<2>());
      }
    }
    const VdtMap2 map = VdtMap2::build(occupancy_from_points<2>(map_points, 0.02, 1.0));
    const ScanPoints obs = ex.observations(frames[i]);
    const Eigen::Rotation2Dd rot(given[i][2]);
    std::size_t near = 0;  // within 5 cm of the others' boundaries at the given pose
    for (const Eigen::Vector2d& p : obs.points) {
      near += map.value(rot * p + given[i].head<2>()).norm() < 0.05;
    }
    VdtOptimizerOptions oo;
    oo.sensor.gate = 0.1;  // five cells
    const VdtOptimizer opt(map, oo);
    const auto error_from = [&](const Pose2& start) {
      const Eigen::Vector3d e = pose_error(opt.solve(obs, start).pose, given[i]);
      return Eigen::Vector2d(e.head<2>().norm(), std::abs(e[2]) * 180.0 / M_PI);
    };
    const Eigen::Vector2d at = error_from(given[i]);
    const Eigen::Vector2d off = error_from(given[i] + Pose2(0.04, 0.03, M_PI / 180.0));
    const double pct = 100.0 * static_cast<double>(near) / static_cast<double>(obs.size());
    char line[256];
    std::snprintf(line, sizeof line, "%zu,%zu,%.1f,%.4f,%.3f,%.4f,%.3f\n", i + 1, obs.size(), pct,
                  at[0], at[1], off[0], off[1]);
    csv << line;
    std::printf(
        "  frame %zu: %zu points, %.0f %% within 5 cm of the others' map; from the given "
        "pose %.3f m %.2f deg, from 5 cm / 1 deg off %.3f m %.2f deg\n",
        i + 1, obs.size(), pct, at[0], at[1], off[0], off[1]);
  }
  std::printf("[done] %s/kinect_relative.csv\n", out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"PMD localization with RGB-D ground boundaries and landmark bearings (3.4.5)"};
  std::string out = "out/pmd_rgbd";
  std::uint64_t seed = 1;
  std::size_t frames = 0;
  bool verbose = false;
  double correlation_length = 2.0;
  bool schmidt = false;
  std::string kinect, calibration;
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--seed", seed, "seed of the park, the drive and all noise")
      ->capture_default_str();
  app.add_option("--frames", frames, "frames to run (0: the whole ~500 m drive)")
      ->capture_default_str();
  app.add_flag("--verbose", verbose, "one line per frame");
  app.add_option("--map-correlation-length", correlation_length,
                 "side of the squares whose map errors are shared (m, 0: independent)")
      ->capture_default_str();
  app.add_flag("--schmidt-map-errors", schmidt,
               "carry the squares' map errors from frame to frame (VdtEkfOptions::"
               "schmidt_map_errors) instead of reporting each frame's map term on top");
  app.add_option("--kinect", kinect,
                 "instead: relative localization between the recorded RGB-D frames of this folder")
      ->check(CLI::ExistingDirectory);
  app.add_option("--calibration", calibration,
                 "with --kinect: the camera's calibration file (default: Kinect v1 intrinsics)")
      ->check(CLI::ExistingFile);
  CLI11_PARSE(app, argc, argv);

  try {
    if (!kinect.empty()) return kinect_study(kinect, calibration, out);
    std::filesystem::create_directories(out);
    // ------------------------------------------------------------------ park, map, drive
    ParkSceneOptions po;
    po.seed = seed;
    const ParkScene scene = generate_park(po);
    const double resolution = 0.05;
    const OccupancyGrid<2> boundaries = scene.boundary_map(resolution);
    const VdtMap2 map = VdtMap2::build(boundaries);
    std::printf(
        "[park] %.0f x %.0f m, map %d x %d cells at %.2f m, %zu lamp posts, %zu obstacles\n",
        po.width, po.depth, boundaries.size().x(), boundaries.size().y(), resolution,
        scene.lamp_posts.size(), scene.obstacles.size());
    ScooterDriveOptions dopt;
    dopt.seed = seed;
    const ScooterDrive drive = simulate_scooter_drive(scene, dopt);
    std::size_t n = drive.truth.size();
    if (frames > 0) n = std::min(n, frames);
    std::printf("[drive] %zu frames at %.0f Hz (%.0f s)\n", n, dopt.frame_rate, drive.time[n - 1]);

    // ------------------------------------------------------------------ front end and filters
    const uav_camera::CameraCalibration calibration = default_rgbd_calibration();
    const Eigen::Isometry3d camera_to_robot = default_rear_camera();
    // Canny on the blurred image places an edge within the blur's sigma: that is the pixel noise
    // of a boundary point (the sensor's depth noise stays the front end's default, Kinect-class).
    GroundBoundaryOptions bo;
    bo.noise.sigma_pixel = bo.blur_sigma;
    const GroundBoundaryExtractor extractor(uav_camera::PinholeCamera(calibration), camera_to_robot,
                                            bo);
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
    VdtEkfLocalizer vdt(map, eo, "vdt-ekf");
    VdtEkfLocalizer fused(map, eo, "vdt-ekf+bearings");
    // The start: within 10 cm and 0.02 rad, as a GNSS fix and a compass would give it.
    const Eigen::Matrix3d p0 = Eigen::Vector3d(0.01, 0.01, 0.0004).asDiagonal();
    for (VdtEkfLocalizer* f : {&vdt, &fused}) f->reset(drive.truth[0], p0);
    // The landmark-only filter and dead reckoning need no map: the same prediction on (x, P).
    Pose2 landmark_x = drive.truth[0], dead = drive.truth[0];
    Eigen::Matrix3d landmark_p = p0, dead_p = p0;
    std::vector<Trace> traces{{"vdt-ekf", {}, {}, 0.0, true},
                              {"vdt-ekf+bearings", {}, {}, 0.0, true},
                              {"bearings", {}, {}, 0.0, false},
                              {"odometry", {}, {}, 0.0, false}};

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
      front_ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      if (k == shown) {
        shown_colour = frame.colour;
        shown_boundaries = b;
      }
      const std::vector<BearingDetection> z = detect_landmarks(scene, truth, det, rng);
      const OdometryStep step = k == 0 ? OdometryStep{} : drive.odometry[k];
      const auto timed = [&](Trace& t, auto&& f) {
        const auto t1 = Clock::now();
        f();
        t.ms += std::chrono::duration<double, std::milli>(Clock::now() - t1).count();
      };
      timed(traces[0], [&] {
        const LocalizationResult r = vdt.update(step, obs);
        traces[0].estimate.push_back(r.pose);
        traces[0].covariance.push_back(r.covariance);
      });
      timed(traces[1], [&] {
        (void)fused.update(step, obs);
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
          std::printf(" | %s (%.3f %.3f %.4f) 2sd (%.3f %.3f %.4f)", t.name.c_str(), e[0], e[1],
                      e[2], 2.0 * std::sqrt(t.covariance[k](0, 0)),
                      2.0 * std::sqrt(t.covariance[k](1, 1)),
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

    // ------------------------------------------------------------------ metrics
    std::ofstream csv(out + "/table.csv");
    csv << "method,frames,pos_rmse_m,yaw_rmse_rad,anees,anees_lo,anees_hi,within_2sigma_pct,"
           "ms_per_frame,anees_left_out\n";
    std::ofstream md(out + "/table.md");
    md << "| method | frames | pos RMSE (m) | yaw RMSE (rad) | ANEES [95 %] | within 2σ (x and y) "
          "% | ms/frame |\n|---|---|---|---|---|---|---|\n";
    std::printf("\n%-18s %6s %9s %9s %22s %8s %8s\n", "method", "frames", "pos[m]", "yaw[rad]",
                "ANEES [95%]", "2sig%", "ms");
    for (const Trace& t : traces) {
      std::vector<double> pos, yaw, nees_values;
      std::size_t within = 0;
      for (std::size_t k = 0; k < n; ++k) {
        const Eigen::Vector3d e = pose_error(t.estimate[k], drive.truth[k]);
        pos.push_back(e.head<2>().norm());
        yaw.push_back(e[2]);
        nees_values.push_back(eval::nees(t.estimate[k], drive.truth[k], t.covariance[k]));
        within += std::abs(e[0]) <= 2.0 * std::sqrt(t.covariance[k](0, 0)) &&
                  std::abs(e[1]) <= 2.0 * std::sqrt(t.covariance[k](1, 1));
      }
      const eval::AneesResult a = eval::anees(nees_values, 3);
      const double pct = 100.0 * static_cast<double>(within) / static_cast<double>(n);
      const double ms = t.ms / static_cast<double>(n) + (t.uses_frames ? front_ms : 0.0);
      char line[512];
      std::snprintf(line, sizeof line, "%s,%zu,%.4f,%.5f,%.3f,%.3f,%.3f,%.1f,%.3f,%zu\n",
                    t.name.c_str(), n, rms(pos), rms(yaw), a.anees, a.interval.lower,
                    a.interval.upper, pct, ms, n - a.count);
      const std::string note = eval::left_out_note(a, n);
      csv << line;
      std::snprintf(line, sizeof line,
                    "| %s | %zu | %.4f | %.5f | %.2f [%.2f, %.2f]%s | %.1f | %.3f |\n",
                    t.name.c_str(), n, rms(pos), rms(yaw), a.anees, a.interval.lower,
                    a.interval.upper, note.empty() ? "" : (" (" + note + ")").c_str(), pct, ms);
      md << line;
      std::printf("%-18s %6zu %9.4f %9.5f %8.2f [%.2f,%.2f] %8.1f %8.2f\n", t.name.c_str(), n,
                  rms(pos), rms(yaw), a.anees, a.interval.lower, a.interval.upper, pct, ms);
    }
    md << "\nFront end (boundaries, back-projection, pruning): "
       << std::to_string(front_ms).substr(0, 5)
       << " ms per frame, included in ms/frame of the filters that use frames.\n";

    // ------------------------------------------------------------------ figures
    std::printf("\n[figures] writing PNGs to %s\n", out.c_str());
    const GridFrame<2>& gf = boundaries.frame();
    const double x0 = gf.origin().x(), y0 = gf.origin().y();
    const double x1 = x0 + boundaries.size().x() * gf.resolution();
    const double y1 = y0 + boundaries.size().y() * gf.resolution();
    {  // Fig. 3.24: trajectories over the map
      viz::Figure fig(1600, static_cast<int>(1600.0 * (y1 - y0) / (x1 - x0)) + 150, 1, 1);
      fig.title("PMD trajectories over the boundary map (Fig. 3.24)");
      auto& ax = fig.axes();
      ax.image(viz::occupancy_image(boundaries), x0, x1, y0, y1)
          .equal_aspect()
          .xlabel("x [m]")
          .ylabel("y [m]");
      std::vector<double> tx, ty;
      for (std::size_t k = 0; k < n; ++k) {
        tx.push_back(drive.truth[k][0]);
        ty.push_back(drive.truth[k][1]);
      }
      ax.line(tx, ty, viz::Style().with_color({0, 0, 0}).with_width(2.0).with_label("truth"));
      for (std::size_t m = 0; m < traces.size(); ++m) {
        std::vector<double> ex, ey;
        for (const Pose2& p : traces[m].estimate) {
          ex.push_back(p[0]);
          ey.push_back(p[1]);
        }
        ax.line(ex, ey,
                viz::Style()
                    .with_color(viz::kColorCycle[m])
                    .with_width(1.2)
                    .with_label(traces[m].name));
      }
      std::vector<double> lx, ly;
      for (const Landmark2& l : landmarks) {
        lx.push_back(l.position.x());
        ly.push_back(l.position.y());
      }
      ax.scatter(lx, ly,
                 viz::Style()
                     .with_color({200, 30, 30})
                     .with_marker(viz::Marker::kCross, 9)
                     .with_label("landmarks"));
      fig.save_png(out + "/trajectories.png");
    }
    {  // Fig. 3.23: errors with +-2 sigma of vdt-ekf and vdt-ekf+bearings
      viz::Figure fig(1600, 1000, 3, 1);
      fig.title("vdt-ekf (boundaries) and vdt-ekf+bearings: errors with 2-sigma bands (Fig. 3.23)");
      const char* comp[3] = {"x error [m]", "y error [m]", "yaw error [rad]"};
      for (int c = 0; c < 3; ++c) {
        auto& ax = fig.axes(c, 0);
        double span = 0.0;
        for (std::size_t m : {0u, 1u}) {
          std::vector<double> t, e, lo, hi;
          for (std::size_t k = 0; k < n; ++k) {
            const Eigen::Vector3d err = pose_error(traces[m].estimate[k], drive.truth[k]);
            const double s = 2.0 * std::sqrt(std::max(0.0, traces[m].covariance[k](c, c)));
            t.push_back(drive.time[k]);
            e.push_back(err[c]);
            lo.push_back(-s);
            hi.push_back(s);
            span = std::max({span, 1.2 * std::abs(err[c]), 1.2 * s});
          }
          ax.band(t, lo, hi,
                  viz::Style()
                      .with_color(viz::kColorCycle[m])
                      .with_alpha(0.25)
                      .with_label(traces[m].name + " +-2 sigma"))
              .line(t, e,
                    viz::Style()
                        .with_color(viz::kColorCycle[m])
                        .with_width(1.2)
                        .with_label(traces[m].name));
        }
        span = std::min(span, c == 2 ? 0.2 : 1.0);
        ax.ylim(-span, span).ylabel(comp[c]);
        if (c == 2) ax.xlabel("time [s]");
      }
      fig.save_png(out + "/errors.png");
    }
    if (!shown_colour.empty()) {  // one frame: kept boundary pixels over the colour image
      viz::Figure fig(1000, 820, 1, 1);
      fig.title("Frame " + std::to_string(shown) + ": ground boundaries kept (" +
                std::to_string(shown_boundaries.points.size()) + ") and pruned (" +
                std::to_string(shown_boundaries.pruned) + ")");
      const int h = shown_colour.rows;
      std::vector<double> ku, kv;
      for (const BoundaryPoint& p : shown_boundaries.points) {
        ku.push_back(p.pixel.x());
        kv.push_back(h - 1 - p.pixel.y());
      }
      fig.axes()
          .image(to_rgb(shown_colour), -0.5, shown_colour.cols - 0.5, -0.5, h - 0.5)
          .equal_aspect()
          .scatter(ku, kv,
                   viz::Style()
                       .with_color({30, 230, 30})
                       .with_marker(viz::Marker::kCircle, 3)
                       .with_label("kept boundary pixels"))
          .xlabel("u [px]")
          .ylabel("image row from the bottom [px]");
      fig.save_png(out + "/frame.png");
    }
    std::printf("[done] %s/table.csv, table.md, errors.png, trajectories.png, frame.png\n",
                out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vdtnav_pmd_rgbd: %s\n", e.what());
    return 1;
  }
  return 0;
}
