// UAV downward-camera localization (thesis 3.4.3, Dataset 3; Figs. 3.13-3.14): a simulated flight
// over a figure-of-eight road marked on a runway (MBZIRC 2017 style), or over a real aerial
// photograph laid on the ground (--texture). Every frame is rendered from the true pose (lens
// distortion, sensor noise, motion blur, an exposure change), its edges are projected to the
// ground with the noisy IMU roll/pitch and laser altitude, and three localizers run side by side
// on the same observations: vdt-opt, vdt-ekf and the UDT chamfer baseline udt-opt.
//
//   vdtnav_uav_camera [--out DIR] [--seed N] [--frames N] [--altitude M] [--texture FILE]
//                     [--solver default|dense|ceres] [--verbose]
//
// Writes DIR/table.csv (method,frames,localized_pct,pos_rmse_m,yaw_rmse_rad,anees,anees_lo,
// anees_hi,recovery_s,ms_per_frame), table.md, trajectory.png (Fig. 3.13), errors_vdt_opt.png and
// errors_vdt_ekf.png (Fig. 3.14), frame.png, and the marking map (map.png + map.yaml) it localizes
// on, read back through the map_server reader as a user's map would be.
#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "vdtnav/estimation/udt_localizers.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/uav_camera/ground_renderer.hpp"
#include "vdtnav/uav_camera/marking_map.hpp"
#include "vdtnav/uav_camera/runway_scene.hpp"
#include "vdtnav/uav_camera/uav_camera_front_end.hpp"
#include "vdtnav/uav_camera/uav_flight.hpp"
#include "vdtnav/viz/viz.hpp"

namespace {

using namespace vdtnav;
using namespace vdtnav::uav_camera;
using Clock = std::chrono::steady_clock;

constexpr double kPi = 3.14159265358979323846;

/// One method's run over the flight.
struct Trace {
  std::string name;
  std::vector<Pose2> estimate;
  std::vector<Eigen::Matrix3d> covariance;
  std::vector<char> has_cov;
  std::vector<LocalizationStatus> status;
  std::vector<int> iterations;
  double ms = 0.0;  // localizer time, all frames
};

/// A camera like the thesis's perspective camera: 640 x 480, ~60 degree horizontal field of view,
/// a mild barrel distortion.
CameraCalibration default_camera() {
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  const double f = 0.5 * c.width / std::tan(0.5 * 60.0 * kPi / 180.0);  // 554 px
  c.camera_matrix << f, 0.0, 319.5, 0.0, f, 239.5, 0.0, 0.0, 1.0;
  c.distortion = {-0.12, 0.03, 0.0005, -0.0003, 0.0};
  return c;
}

viz::RgbImage to_rgb(const cv::Mat& gray) {
  viz::RgbImage img(gray.cols, gray.rows);
  for (int r = 0; r < gray.rows; ++r)
    for (int c = 0; c < gray.cols; ++c) {
      const std::uint8_t v = gray.at<std::uint8_t>(r, c);
      std::uint8_t* px = &img.rgb[3 * (static_cast<std::size_t>(r) * gray.cols + c)];
      px[0] = px[1] = px[2] = v;
    }
  return img;
}

double rms(const std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s / static_cast<double>(v.size()));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"UAV downward-camera localization on a VDT map of ground markings (thesis 3.4.3)"};
  std::string out = "out/uav_camera";
  std::uint64_t seed = 1;
  std::size_t frames = 1200;
  double altitude = 15.0;
  std::string texture_path;
  bool verbose = false;
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--seed", seed, "seed of the scene's texture, the flight and all noise")
      ->capture_default_str();
  app.add_option("--frames", frames, "frames at 10 Hz")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{20}, std::size_t{100000}));
  app.add_option("--altitude", altitude,
                 "mean altitude, m; the flight climbs and descends by a third of it")
      ->capture_default_str()
      ->check(CLI::Range(2.0, 200.0));
  app.add_option("--texture", texture_path,
                 "a photograph laid on the ground instead of the runway (its edges are the map)")
      ->check(CLI::ExistingFile);
  std::string solver = "default";
  app.add_option("--solver", solver, "vdt-opt's scan solver: default, dense or ceres")
      ->check(CLI::IsMember({"default", "dense", "ceres"}))
      ->capture_default_str();
  app.add_flag("--verbose", verbose, "one line per frame: points, explained fraction, status");
  CLI11_PARSE(app, argc, argv);

  try {
    std::filesystem::create_directories(out);
    const bool photo = !texture_path.empty();
    const CameraCalibration calibration = default_camera();
    const UavRig rig;

    // ------------------------------------------------------------------ scene and map
    std::printf("[scene] %s\n", photo ? ("photograph " + texture_path).c_str()
                                      : "figure-of-eight road on a runway (generated)");
    RunwaySceneOptions so;
    so.seed = seed;
    double photo_resolution = 0.0;
    if (photo) {
      // The eight of the flight, scaled to fit inside the photograph laid on the ground.
      so.runway_length = 52.0;
      so.runway_width = 24.0;
      so.loop_radius = 7.0;
      so.loop_separation = 22.0;
      so.grass_margin = 2.0;
    }
    RunwayScene scene = make_runway_scene(so);
    const std::string map_prefix = out + "/map";
    OccupancyGrid<2> boundaries;
    if (photo) {
      const cv::Mat img = cv::imread(texture_path, cv::IMREAD_GRAYSCALE);
      VDTNAV_CHECK(!img.empty(), "cannot read the photograph '" + texture_path + "'");
      // Laid at a scale that makes it cover the flight's footprint with a margin (0.1 m per pixel
      // for a 640 x 480 photograph: 64 m x 48 m).
      photo_resolution = 64.0 / img.cols;
      const Eigen::Vector2d origin(-0.5 * img.cols * photo_resolution,
                                   -0.5 * img.rows * photo_resolution);
      scene.texture = photograph_texture(img, photo_resolution, origin);
      EdgeOptions eo;  // the map: every edge of the photograph, no subsampling
      eo.max_points = 0;
      boundaries = edge_grid(img, photo_resolution, origin, eo);
      scene.runway = Eigen::AlignedBox2d(
          origin, origin + Eigen::Vector2d(img.cols, img.rows) * photo_resolution);
    } else {
      save_marking_map(map_prefix, scene);
      // The user's path: the map_server YAML + PNG read back.
      boundaries = marking_boundaries(occupancy(load_ros_map(map_prefix + ".yaml")));
    }
    const VdtMap2 map = photo ? VdtMap2::build(boundaries) : load_marking_map(map_prefix + ".yaml");
    std::printf("[map] %d x %d cells at %.3f m\n", boundaries.size().x(), boundaries.size().y(),
                boundaries.frame().resolution());

    // ------------------------------------------------------------------ flight
    UavFlightOptions fo;
    fo.seed = seed;
    fo.frames = frames;
    fo.altitude_min = altitude * 2.0 / 3.0;
    fo.altitude_max = altitude * 4.0 / 3.0;
    if (photo) {
      fo.off_runway_stretches = false;
      fo.speed = 3.0;
    }
    const std::vector<UavFlightSample> flight = simulate_uav_flight(scene, rig, fo);
    std::printf("[flight] %zu frames at %.0f Hz, altitude %.1f-%.1f m\n", flight.size(),
                fo.frame_rate, fo.altitude_min, fo.altitude_max);

    // ------------------------------------------------------------------ front end, localizers
    UavCameraOptions co;  // pixel, IMU and laser noise as the flight's sensors
    co.noise.sigma_roll = fo.sigma_roll;
    co.noise.sigma_pitch = fo.sigma_pitch;
    co.noise.sigma_laser_range = fo.sigma_laser_range;
    // Errors correlated along a line: the map's rasterisation of a marking (a staircase within
    // +-half a cell: resolution / sqrt(12)), one offset per metre of line.
    co.noise.sigma_correlated = map.resolution() / std::sqrt(12.0);
    co.noise.correlation_length = 1.0;
    const UavCameraFrontEnd front(calibration, rig, co);
    const GroundRenderer renderer(calibration, rig);

    // Settings derived from the camera and the map (README, "UAV camera"): a frame counts as
    // features when at least 50 edge points are explained; an edge point is explained within
    // 2 map cells (+ the 5 cm that a 0.2 degree attitude error moves the ground at 15 m); the
    // gate is 10 map cells. Gap bridging (scan-to-scan matching) is off: grass edges are texture.
    const double res = map.resolution();
    const int min_explained = 50;
    GuessSearchOptions search;
    search.explained_distance = 2.0 * res + altitude * fo.sigma_roll;
    search.search_below = 0.5;
    search.accept_fraction = 0.25;
    search.reentry_fraction = 0.4;
    search.check_every_jump = true;  // the eight's legs and lane lines repeat
    search.truncation = 0.5;
    search.max_window_xy = 6.0;
    search.max_window_yaw = 0.6;
    // Odometry noise as the flight's (uav_flight.hpp): 5 % of the distance per axis, 5 % of the
    // turn + 0.005 rad/s in yaw.
    MotionNoise odo;
    odo.a_tt = fo.odometry_sigma_xy_per_m;
    odo.a_tr = 0.0;
    odo.a_rr = fo.odometry_sigma_yaw_per_rad;
    odo.a_rt = 0.0;
    odo.floor_t = 1e-4;
    odo.floor_r = fo.odometry_sigma_yaw_per_s / fo.frame_rate;
    search.odometry_noise = odo;

    VdtOptimizerOptions oo;
    oo.sensor.gate = 10.0 * res;
    oo.min_inliers = min_explained;
    oo.max_iterations = 50;
    // Edges of clutter (cracks, stains, grass) near a marking would pull the solution: a Cauchy
    // loss at the explained distance discounts them.
    oo.loss = RobustLoss::kCauchy;
    oo.loss_scale = search.explained_distance;
    oo.search = search;
    oo.bridge.enabled = false;
    // Frames with one marking line in view constrain nothing along it: the prediction holds that
    // direction (a maximum a posteriori solve) instead of the solve sliding along the line.
    oo.odometry_prior = true;
    if (solver != "default")
      oo.solver = solver == "dense" ? ScanSolver::kDense : ScanSolver::kCeres;
    VdtEkfOptions eo;
    eo.sensor.gate = 10.0 * res;
    eo.min_inliers = min_explained;
    eo.motion = MotionModelKind::kOdometryIncrement;
    eo.noise = odo;
    eo.search = search;
    eo.optimizer_start = true;  // the iterations start where the optimizer lands
    eo.start = oo;
    eo.start.search.enabled = false;
    eo.max_iterations = 5;
    UdtOptions uo;
    uo.gate = 10.0 * res;
    uo.min_inliers = min_explained;
    uo.motion = MotionModelKind::kOdometryIncrement;
    uo.noise = odo;

    std::vector<std::unique_ptr<Localizer2D>> methods;
    methods.push_back(std::make_unique<VdtOptimizationLocalizer>(map, oo));
    methods.push_back(std::make_unique<VdtEkfLocalizer>(map, eo));
    methods.push_back(std::make_unique<UdtOptimizationLocalizer>(boundaries, uo));
    const Eigen::Matrix3d p0 = Eigen::Vector3d(0.25, 0.25, 0.01).asDiagonal();
    std::vector<Trace> traces(methods.size());
    for (std::size_t m = 0; m < methods.size(); ++m) {
      methods[m]->reset(flight[0].pose, p0);
      traces[m].name = methods[m]->name();
    }

    // ------------------------------------------------------------------ the run
    std::mt19937_64 rng(seed * 7919 + 17);
    const VdtSensorModel truth_model(map, oo.sensor);
    std::vector<char> features(flight.size(), 0);
    std::vector<double> front_ms(flight.size(), 0.0);
    std::vector<std::size_t> n_edges(flight.size(), 0);
    const std::size_t shown = flight.size() / 5;
    cv::Mat shown_image;
    CameraFrame shown_frame;
    std::printf("[run] rendering, extracting and localizing %zu frames\n", flight.size());
    for (std::size_t k = 0; k < flight.size(); ++k) {
      const UavFlightSample& s = flight[k];
      RenderOptions ro;
      ro.motion_blur_px = 1.5;  // 4 m/s x 10 ms exposure at ~2.7 cm per pixel
      ro.blur_angle = 0.0;
      // The light changes over the flight (a cloud): +-25 % gain.
      ro.exposure_gain = 1.0 + 0.25 * std::sin(2.0 * kPi * s.time / 60.0);
      const cv::Mat image = renderer.render(scene.texture, s.world_from_body, ro, rng);
      const auto t0 = Clock::now();
      const CameraFrame frame = front.observe(image, s.reading);
      front_ms[k] = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      n_edges[k] = frame.observations.size();
      if (k == shown) {
        shown_image = image;
        shown_frame = frame;
      }
      // "Sees the road": at least min_explained edge points explained at the true pose.
      features[k] =
          explained_fraction(truth_model, frame.observations, s.pose, search.explained_distance) *
                      static_cast<double>(frame.observations.size()) >=
                  min_explained
              ? 1
              : 0;
      for (std::size_t m = 0; m < methods.size(); ++m) {
        const auto t1 = Clock::now();
        const LocalizationResult r = k == 0 ? methods[m]->update(OdometryStep{}, frame.observations)
                                            : methods[m]->update(s.odometry, frame.observations);
        traces[m].ms += std::chrono::duration<double, std::milli>(Clock::now() - t1).count();
        traces[m].estimate.push_back(r.pose);
        traces[m].covariance.push_back(r.covariance);
        traces[m].has_cov.push_back(
            r.has_covariance && r.status == LocalizationStatus::kConverged ? 1 : 0);
        traces[m].status.push_back(r.status);
        traces[m].iterations.push_back(r.iterations);
      }
      if (verbose) {
        std::printf(
            "frame %zu: %zu points, explained at the truth %.2f, features %d", k,
            frame.observations.size(),
            explained_fraction(truth_model, frame.observations, s.pose, search.explained_distance),
            features[k]);
        for (const Trace& t : traces) {
          const Eigen::Vector3d e = pose_error(t.estimate[k], s.pose);
          std::printf(" | %s %s %.3f m %.4f rad %d it", t.name.c_str(), to_string(t.status[k]),
                      e.head<2>().norm(), e[2], t.iterations[k]);
        }
        std::printf("\n");
      }
      if ((k + 1) % 100 == 0 || k + 1 == flight.size()) {
        std::printf("  frame %zu/%zu  edges %zu  vdt-opt error %.3f m\n", k + 1, flight.size(),
                    n_edges[k], pose_error(traces[0].estimate[k], s.pose).head<2>().norm());
        std::fflush(stdout);
      }
    }

    // ------------------------------------------------------------------ metrics
    double mean_front_ms = 0.0;
    for (double v : front_ms) mean_front_ms += v / static_cast<double>(front_ms.size());
    std::size_t with_features = 0;
    for (char f : features) with_features += f ? 1 : 0;
    std::ofstream csv(out + "/table.csv");
    csv << "method,frames,localized_pct,pos_rmse_m,yaw_rmse_rad,anees,anees_lo,anees_hi,"
           "recovery_s,ms_per_frame,anees_left_out\n";
    std::ofstream md(out + "/table.md");
    md << "| method | frames | localized % | pos RMSE (m) | yaw RMSE (rad) | ANEES [95 %] | "
          "recovery (s) | ms/frame |\n|---|---|---|---|---|---|---|---|\n";
    std::printf("\n%-8s %6s %9s %9s %9s %18s %9s %8s\n", "method", "frames", "local.%", "pos[m]",
                "yaw[rad]", "ANEES [95%]", "recov[s]", "ms");
    for (const Trace& t : traces) {
      const bool has_cov = t.name != "udt-opt";
      std::vector<double> pos, yaw, nees_values;
      std::size_t localized = 0;
      for (std::size_t k = 0; k < flight.size(); ++k) {
        if (!features[k] || t.status[k] != LocalizationStatus::kConverged) continue;
        ++localized;
        const Eigen::Vector3d e = pose_error(t.estimate[k], flight[k].pose);
        pos.push_back(e.head<2>().norm());
        yaw.push_back(e[2]);
        if (t.has_cov[k])
          nees_values.push_back(eval::nees(t.estimate[k], flight[k].pose, t.covariance[k]));
      }
      // Re-acquisition: from each return of features after a feature-poor span, the time until
      // the position error is below 0.2 m.
      std::vector<double> recovery;
      for (std::size_t k = 1; k < flight.size(); ++k) {
        if (!(features[k] && !features[k - 1])) continue;
        for (std::size_t j = k; j < flight.size(); ++j) {
          if (pose_error(t.estimate[j], flight[j].pose).head<2>().norm() < 0.2) {
            recovery.push_back(flight[j].time - flight[k].time);
            break;
          }
          if (j + 1 == flight.size()) recovery.push_back(flight[j].time - flight[k].time);
        }
      }
      double recovery_s = 0.0;
      for (double r : recovery) recovery_s += r / static_cast<double>(recovery.size());
      if (recovery.empty()) recovery_s = std::nan("");
      double anees = std::nan(""), lo = std::nan(""), hi = std::nan("");
      std::size_t left_out = with_features;
      std::string note;  // the frames that see the road the ANEES leaves out, and why
      if (has_cov && !nees_values.empty()) {
        const eval::AneesResult a = eval::anees(nees_values, 3);
        anees = a.anees;
        lo = a.interval.lower;
        hi = a.interval.upper;
        left_out = with_features - a.count;
        note = eval::left_out_note(a, with_features, "not localized or without a covariance");
      }
      const double pct = with_features ? 100.0 * localized / with_features : 0.0;
      int counts[5] = {0, 0, 0, 0, 0};
      for (LocalizationStatus st : t.status) ++counts[static_cast<int>(st)];
      std::printf(
          "  %s statuses: converged %d, not converged %d, too few %d, diverged %d, refused %d\n",
          t.name.c_str(), counts[0], counts[1], counts[2], counts[3], counts[4]);
      if (has_cov) {  // per-component normalised squared errors: which one is off
        Eigen::Vector3d z = Eigen::Vector3d::Zero();
        int nz = 0;
        for (std::size_t k = 0; k < flight.size(); ++k) {
          if (!features[k] || !t.has_cov[k]) continue;
          const Eigen::Vector3d e = pose_error(t.estimate[k], flight[k].pose);
          for (int c = 0; c < 3; ++c) z[c] += e[c] * e[c] / t.covariance[k](c, c);
          ++nz;
        }
        if (nz > 0) z /= nz;
        std::printf("  %s mean e^2/sigma^2: x %.2f, y %.2f, yaw %.2f (1 when calibrated)\n",
                    t.name.c_str(), z[0], z[1], z[2]);
      }
      const double ms = t.ms / flight.size() + mean_front_ms;
      char line[512];
      std::snprintf(line, sizeof line, "%s,%zu,%.2f,%.4f,%.5f,%.3f,%.3f,%.3f,%.2f,%.3f,%zu\n",
                    t.name.c_str(), flight.size(), pct, rms(pos), rms(yaw), anees, lo, hi,
                    recovery_s, ms, left_out);
      csv << line;
      std::snprintf(
          line, sizeof line, "| %s | %zu | %.1f | %.4f | %.5f | %s | %s | %.2f |\n", t.name.c_str(),
          flight.size(), pct, rms(pos), rms(yaw),
          has_cov ? (std::to_string(anees).substr(0, 5) + " [" + std::to_string(lo).substr(0, 4) +
                     ", " + std::to_string(hi).substr(0, 4) + "]" +
                     (note.empty() ? "" : " (" + note + ")"))
                        .c_str()
                  : "—",
          recovery.empty() ? "—" : std::to_string(recovery_s).substr(0, 4).c_str(), ms);
      md << line;
      std::printf("%-8s %6zu %9.1f %9.4f %9.5f %8.2f [%.2f,%.2f] %9.2f %8.2f\n", t.name.c_str(),
                  flight.size(), pct, rms(pos), rms(yaw), anees, lo, hi, recovery_s, ms);
    }
    md << "\nFrames that see the road (>= " << min_explained
       << " edge points explained at the true pose): " << with_features << " of " << flight.size()
       << ". Front end (edges + ground projection): " << std::to_string(mean_front_ms).substr(0, 4)
       << " ms per frame, included in ms/frame.\n";
    std::printf("frames that see the road: %zu of %zu; front end %.2f ms per frame\n",
                with_features, flight.size(), mean_front_ms);

    // ------------------------------------------------------------------ figures
    std::printf("\n[figures] writing PNGs to %s\n", out.c_str());
    const GridFrame<2>& gf = boundaries.frame();
    const double x0 = gf.origin().x(), y0 = gf.origin().y();
    const double x1 = x0 + boundaries.size().x() * gf.resolution();
    const double y1 = y0 + boundaries.size().y() * gf.resolution();
    {  // Fig. 3.13: the trajectory against the truth over the map
      viz::Figure fig(1600, static_cast<int>(1600.0 * (y1 - y0) / (x1 - x0)) + 150, 1, 1);
      fig.title("UAV trajectory: truth and vdt-opt on localized frames (Fig. 3.13)");
      auto& ax = fig.axes();
      ax.image(viz::occupancy_image(boundaries), x0, x1, y0, y1)
          .equal_aspect()
          .xlabel("x [m]")
          .ylabel("y [m]");
      std::vector<double> tx, ty, ex, ey, gx, gy;
      for (std::size_t k = 0; k < flight.size(); ++k) {
        tx.push_back(flight[k].pose[0]);
        ty.push_back(flight[k].pose[1]);
        if (traces[0].status[k] == LocalizationStatus::kConverged) {
          ex.push_back(traces[0].estimate[k][0]);
          ey.push_back(traces[0].estimate[k][1]);
        }
        if (!features[k]) {
          gx.push_back(flight[k].pose[0]);
          gy.push_back(flight[k].pose[1]);
        }
      }
      ax.line(tx, ty, viz::Style().with_color({0, 0, 0}).with_width(1.5).with_label("truth"));
      ax.scatter(gx, gy,
                 viz::Style()
                     .with_color({160, 160, 160})
                     .with_marker(viz::Marker::kCircle, 5)
                     .with_label("feature-poor frames"));
      ax.scatter(ex, ey,
                 viz::Style()
                     .with_color(viz::kColorCycle[0])
                     .with_marker(viz::Marker::kCross, 5)
                     .with_label("vdt-opt (converged)"));
      fig.save_png(out + "/trajectory.png");
    }
    for (int m : {0, 1}) {  // Fig. 3.14: x, y, yaw errors with +-2 sigma, feature-poor shaded
      viz::Figure fig(1600, 1000, 3, 1);
      fig.title(traces[m].name + ": errors with 2-sigma bands; grey: frames without features");
      const char* comp[3] = {"x error [m]", "y error [m]", "yaw error [rad]"};
      for (int c = 0; c < 3; ++c) {
        std::vector<double> t, e, lo, hi, shade_lo, shade_hi;
        double span = 0.0;
        for (std::size_t k = 0; k < flight.size(); ++k) {
          const Eigen::Vector3d err = pose_error(traces[m].estimate[k], flight[k].pose);
          const double s = traces[m].has_cov[k]
                               ? 2.0 * std::sqrt(std::max(0.0, traces[m].covariance[k](c, c)))
                               : 0.0;
          t.push_back(flight[k].time);
          const bool ok = traces[m].status[k] == LocalizationStatus::kConverged;
          e.push_back(ok ? err[c] : std::nan(""));
          lo.push_back(-s);
          hi.push_back(s);
          if (ok) span = std::max(span, std::abs(err[c]) * 1.2);
          span = std::max(span, s * 1.2);
        }
        span = std::min(span, c == 2 ? 0.1 : 1.0);
        for (std::size_t k = 0; k < flight.size(); ++k) {
          shade_lo.push_back(features[k] ? 0.0 : -span);
          shade_hi.push_back(features[k] ? 0.0 : span);
        }
        auto& ax = fig.axes(c, 0);
        ax.band(t, shade_lo, shade_hi,
                viz::Style().with_color({150, 150, 150}).with_alpha(0.35).with_label("no features"))
            .band(t, lo, hi, viz::Style().with_label("+-2 sigma"))
            .line(t, e, viz::Style().with_width(1.2).with_label("error"))
            .ylim(-span, span)
            .ylabel(comp[c]);
        if (c == 2) ax.xlabel("time [s]");
      }
      fig.save_png(out + "/errors_" + std::string(m == 0 ? "vdt_opt" : "vdt_ekf") + ".png");
    }
    {  // One frame: its edges in the image, their ground points over the map
      viz::Figure fig(1800, 760, 1, 2);
      fig.title("Frame " + std::to_string(shown) +
                ": edges (left) and their ground projections at "
                "the vdt-opt estimate (right)");
      std::vector<double> eu, ev;
      for (const auto& p : shown_frame.edges) {
        eu.push_back(p.x());
        ev.push_back(calibration.height - 1 - p.y());
      }
      fig.axes(0, 0)
          .image(to_rgb(shown_image), -0.5, calibration.width - 0.5, -0.5, calibration.height - 0.5)
          .equal_aspect()
          .scatter(eu, ev,
                   viz::Style()
                       .with_color({230, 30, 30})
                       .with_marker(viz::Marker::kCircle, 3)
                       .with_label("edge pixels"))
          .xlabel("u [px]")
          .ylabel("image row from the bottom [px]");
      const Pose2 at = traces[0].estimate[shown];
      const Pose2 truth = flight[shown].pose;
      std::vector<double> gx, gy;
      const double c = std::cos(at[2]), s = std::sin(at[2]);
      for (const auto& p : shown_frame.observations.points) {
        gx.push_back(at[0] + c * p.x() - s * p.y());
        gy.push_back(at[1] + s * p.x() + c * p.y());
      }
      const double half = 1.0 * altitude;
      fig.axes(0, 1)
          .image(viz::occupancy_image(boundaries), x0, x1, y0, y1)
          .equal_aspect()
          .xlim(truth[0] - half, truth[0] + half)
          .ylim(truth[1] - 0.75 * half, truth[1] + 0.75 * half)
          .scatter(gx, gy,
                   viz::Style()
                       .with_color({230, 30, 30})
                       .with_marker(viz::Marker::kCircle, 3)
                       .with_label("ground points"))
          .xlabel("x [m]")
          .ylabel("y [m]");
      fig.save_png(out + "/frame.png");
    }
    std::printf(
        "[done] %s/table.csv, table.md, trajectory.png, errors_vdt_opt.png, errors_vdt_ekf.png, "
        "frame.png\n",
        out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vdtnav_uav_camera: %s\n", e.what());
    return 1;
  }
  return 0;
}
