// vdtnav localize3d: 6-DOF (or 4-DOF) localization of 3D LiDAR scans on a 3D map, the way users of
// hdl_localization, DLL or small_gicp run it: map + scan(s) + initial guess -> pose, 6x6 covariance
// and whether the map explains the scan there. One scan: --out is a YAML file; a sequence (several
// --scan, or --scans DIR): --out is a folder with one YAML per scan and trajectory.tum.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "common.hpp"
#include "exit_status.hpp"
#include "parse.hpp"
#include "staged_output.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/global_localization3d.hpp"
#include "vdtnav/estimation/localizer_config.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/estimation/multi_start.hpp"
#include "vdtnav/estimation/recovering_localizer3d.hpp"
#include "vdtnav/estimation/scan_agreement.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/io/imu_table.hpp"
#include "vdtnav/io/scan_run.hpp"
#include "vdtnav/io/tum_trajectory.hpp"
#include "vdtnav/pcl/cloud_observations.hpp"
#include "vdtnav/pcl/point_cloud_file.hpp"
#ifdef VDTNAV_CLI_ROS
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/cloud_sequence.hpp"
#endif

namespace vdtnav::tools {

namespace {

namespace fs = std::filesystem;

struct Localize3dArgs {
  std::string map, scans_dir, init, init_matrix, out, config, crop;
  std::vector<std::string> scans;
  // --bag: a ROS 1 or ROS 2 bag's PointCloud2 topic (vdtnav/ros/cloud_sequence.hpp)
  std::string bag, cloud_topic, odom_topic, imu_topic, odom_frame = "odom",
                                                       base_frame = "base_link";
  std::string lidar_pose;
  std::string imu_csv;  // --imu FILE: t,wx,wy,wz,ax,ay,az
  std::string times;    // --times FILE: a stamp per scan (KITTI's times.txt)
  std::string odom;     // --odom FILE: the odometry's pose per scan (KITTI, or TUM by stamp)
  int dof = 6;
  MapLoadOptions map_options;
  double voxel = -1.0;
  double min_range = 0.0;
  double max_range = std::numeric_limits<double>::infinity();
  double sigma_range = 0.03;
  /// A converged pose explaining less is refused. Real scans of one place explain each other's map
  /// at 34-54 % (libpointmatcher's three consecutive outdoor scans, both ways, at 0.1 m), wrong
  /// minima from an identity guess 3-26 %.
  double min_explained = 0.3;
  bool min_explained_given = false;  // else the settings' localize3d.accept_fraction
  bool multi_start = false;
  bool quiet = false;
  bool print_config = false;
  bool strict = false;
  bool all_poses = false;
  std::string accept_status = "converged";
  /// 4-DOF: the held roll and pitch's standard deviation (radians); NaN: not estimated.
  double attitude_sigma = std::numeric_limits<double>::quiet_NaN();
  int threads = -1;  // --threads; -1: the settings' threads:
};

/// status.csv's header: the scan's time, status, explained fraction, then the upper triangle of
/// the 6 x 6 covariance of (x, y, z, rx, ry, rz), row by row (rx, ry, rz: the rotation vector of
/// the left perturbation, radians).
std::string status_table_header() {
  static const char* const kNames[6] = {"x", "y", "z", "rx", "ry", "rz"};
  std::string h = "t,status,explained";
  for (int i = 0; i < 6; ++i)
    for (int j = i; j < 6; ++j) h += std::string(",") + kNames[i] + kNames[j];
  return h;
}

/// One scan's result, as written.
struct ScanReport {
  std::string scan;
  LocalizationResult3 result;
  double explained = 0.0;
  ScanAgreement agreement;  ///< at the pose reported (scan_agreement.hpp)
  std::size_t readings = 0, cloud_points = 0;
  double read_ms = 0.0, solve_ms = 0.0;
};

/// A scan's time stamp: its file name's when that is a number (stamp_of_name), else its index in
/// the sequence.
double stamp_of(const std::string& path, std::size_t index) {
  return stamp_of_name(path).value_or(static_cast<double>(index));
}

std::string yaml_report(const ScanReport& r, int dof, double explained_distance) {
  std::ostringstream y;
  y.precision(9);
  const Pose3& p = r.result.pose;
  const Eigen::Vector3d rpy = rpy_of(p.linear());
  const Eigen::Quaterniond q(p.linear());
  y << "# vdtnav localize3d: the scan's pose in the map frame (map point = pose * scan point)\n";
  y << "scan: \"" << r.scan << "\"\n";
  y << "status: " << to_string(r.result.status) << "\n";
  y << "dof: " << dof << "\n";
  y << "explained: " << r.explained << "  # fraction of the readings within " << explained_distance
    << " m of the map at the pose\n";
  y << "contradiction: " << r.agreement.contradiction()
    << "  # of the readings the map judges (explained, or their beam passed through a surface of "
       "the map), the share that passed through\n";
  y << "agreement: {explained: " << r.agreement.explained
    << ", contradicted: " << r.agreement.contradicted << ", unknown: " << r.agreement.unknown
    << "}  # readings\n";
  y << "pose:  # 4x4, row by row\n";
  for (int i = 0; i < 4; ++i) {
    y << "  - [";
    for (int j = 0; j < 4; ++j) y << (j ? ", " : "") << p.matrix()(i, j);
    y << "]\n";
  }
  y << "xyz: [" << p.translation().x() << ", " << p.translation().y() << ", " << p.translation().z()
    << "]\n";
  y << "rpy: [" << rpy.x() << ", " << rpy.y() << ", " << rpy.z()
    << "]  # radians, R = Rz(yaw) Ry(pitch) Rx(roll)\n";
  y << "quaternion_xyzw: [" << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]\n";
  y << "has_covariance: " << (r.result.has_covariance ? "true" : "false") << "\n";
  y << "covariance:  # 6x6 of (dx, dy, dz, dtheta_x, dtheta_y, dtheta_z): a left perturbation "
       "in the map frame, pose = Exp(delta) * estimate; m^2, rad^2"
    << (dof == 4 && std::isnan(r.result.covariance(3, 3))
            ? "; .nan rows: roll and pitch held, not estimated (--attitude-sigma gives them one)"
            : "")
    << "\n";
  for (int i = 0; i < 6; ++i) {
    y << "  - [";
    for (int j = 0; j < 6; ++j) {
      const double c = r.result.covariance(i, j);
      y << (j ? ", " : "");
      if (std::isnan(c)) {
        y << ".nan";  // YAML's NaN
      } else {
        y << c;
      }
    }
    y << "]\n";
  }
  y << "readings: " << r.readings << "  # after range limits and voxel downsampling, of "
    << r.cloud_points << " points\n";
  y << "inliers: " << r.result.inliers << "\n";
  y << "iterations: " << r.result.iterations << "  # every solve, coarse levels included\n";
  y << "solves: " << r.result.work.solves << "\n";
  y << "final_cost: " << r.result.final_cost << "\n";
  y << "time_ms: {read: " << r.read_ms << ", solve: " << r.solve_ms << "}\n";
  return y.str();
}

/// One row of status.csv (status_table_header()).
std::string status_row(double t, const ScanReport& r) {
  std::string row;
  char b[64];
  std::snprintf(b, sizeof b, "%.6f,", t);
  row += b;
  row += status_token(r.result.status);
  std::snprintf(b, sizeof b, ",%.4f", r.explained);
  row += b;
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) {
      std::snprintf(b, sizeof b, ",%.9g",
                    r.result.has_covariance ? r.result.covariance(i, j) : std::nan(""));
      row += b;
    }
  }
  return row;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  if (!f) throw IoError(path + ": cannot open for writing");
  f << text;
  if (!f) throw IoError(path + ": write failed");
}

/// The motion between two scans from the IMU's samples (sensor/imu.hpp): the increment
/// preintegrated over [t_prev, t] from the previous scan's estimate and the velocity there, with
/// its covariance (the IMU's noise and bias and the velocity's uncertainty). The velocity at a
/// scan follows from the two estimates before it and the IMU between them, exactly:
/// p_b = p_a + v_a dt + g dt^2 / 2 + R_a dp gives v_a, and v_b = v_a + g dt + R_a dv; its
/// covariance (P_a + P_b)_pos / dt^2. Before two consecutive estimates there is none: 0 +- 2 m/s.
class ImuMotion {
 public:
  ImuMotion(const std::vector<ImuSample>& samples, const ImuNoise& noise)
      : samples_(&samples), noise_(noise) {}

  /// \brief A scan's estimate at t (converged or not: a refused scan's is the prediction).
  void add(double t, const Pose3& pose, const Matrix6d& covariance, bool converged) {
    velocity_known_ = false;
    if (has_prev_ && prev_converged_ && converged && t > prev_t_ &&
        imu_covers(*samples_, prev_t_, t)) {
      // The interval step(t) integrated, when it did.
      const ImuIncrement inc = last_ && last_->t0 == prev_t_ && last_->t1 == t
                                   ? *last_
                                   : integrate_imu(*samples_, prev_t_, t, noise_);
      const Eigen::Vector3d g(0.0, 0.0, -noise_.gravity);
      const double dt = inc.dt;
      const Eigen::Vector3d va = (pose.translation() - prev_pose_.translation() -
                                  0.5 * g * dt * dt - prev_pose_.linear() * inc.delta_p) /
                                 dt;
      velocity_ = va + g * dt + prev_pose_.linear() * inc.delta_v;
      velocity_covariance_ =
          (prev_covariance_.topLeftCorner<3, 3>() + covariance.topLeftCorner<3, 3>()) / (dt * dt);
      velocity_known_ = true;
    }
    last_.reset();
    has_prev_ = true;
    prev_t_ = t;
    prev_pose_ = pose;
    prev_covariance_ = covariance;
    prev_converged_ = converged;
  }

  /// \return the step from the last scan added to a scan at t, or none when the samples do not
  /// cover the interval.
  [[nodiscard]] std::optional<OdometryStep3> step(double t) {
    if (!has_prev_ || !(t > prev_t_) || !imu_covers(*samples_, prev_t_, t)) return std::nullopt;
    last_ = integrate_imu(*samples_, prev_t_, t, noise_);
    const ImuIncrement& inc = *last_;
    const Eigen::Vector3d v = velocity_known_ ? velocity_ : Eigen::Vector3d::Zero();
    const Eigen::Matrix3d sv =
        velocity_known_ ? velocity_covariance_ : Eigen::Matrix3d(4.0 * Eigen::Matrix3d::Identity());
    const ImuRelativePose rp = imu_relative_pose(prev_pose_, v, sv, inc, noise_.gravity);
    OdometryStep3 m;
    m.dt = inc.dt;
    m.delta = rp.delta;
    m.covariance = rp.covariance;
    m.has_covariance = true;
    return m;
  }

  /// \brief Roll and pitch from gravity over the `window` seconds before t, when the samples cover
  /// it and the robot is not accelerating there (attitude_from_gravity).
  [[nodiscard]] std::optional<GravityAttitude> gravity(double t, double window) const {
    if (samples_->empty() || !imu_covers(*samples_, t - window, t)) return std::nullopt;
    const GravityAttitude g = attitude_from_gravity(*samples_, t - window, t, noise_);
    if (g.accelerating) return std::nullopt;
    return g;
  }

 private:
  const std::vector<ImuSample>* samples_;
  ImuNoise noise_;
  bool has_prev_ = false, prev_converged_ = false, velocity_known_ = false;
  double prev_t_ = 0.0;
  Pose3 prev_pose_ = Pose3::Identity();
  Matrix6d prev_covariance_ = Matrix6d::Zero();
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d velocity_covariance_ = Eigen::Matrix3d::Zero();
  std::optional<ImuIncrement> last_;  ///< step()'s, over [prev_t_, t]: add(t) reuses it
};

void run_localize3d(const Localize3dArgs& a) {
  // Options first: a typo must not cost a map build.
  if (a.dof != 6 && a.dof != 4) throw UsageError("localize3d: --dof must be 6 or 4");
  if (!a.init.empty() && !a.init_matrix.empty())
    throw UsageError("localize3d: give --init or --init-matrix, not both");
  const int inputs =
      (a.scans.empty() ? 0 : 1) + (a.scans_dir.empty() ? 0 : 1) + (a.bag.empty() ? 0 : 1);
  if (inputs != 1 && !a.print_config)
#ifdef VDTNAV_CLI_ROS
    throw UsageError("localize3d: give --scan FILE (one or more) or --scans DIR, or --bag BAG");
#else
    throw UsageError("localize3d: give --scan FILE (one or more) or --scans DIR");
#endif
  if (!(a.min_explained >= 0.0 && a.min_explained <= 1.0))
    throw UsageError("localize3d: --min-explained must be in [0, 1]");
  if (!std::isnan(a.attitude_sigma) && !(a.attitude_sigma > 0.0 && std::isfinite(a.attitude_sigma)))
    throw UsageError("localize3d: --attitude-sigma must be a finite number of radians > 0");
  if (!std::isnan(a.attitude_sigma) && a.dof != 4)
    throw UsageError("localize3d: --attitude-sigma is for --dof 4 (roll and pitch held)");
  const std::set<LocalizationStatus> accepted_statuses =
      parse_statuses(a.accept_status, "--accept-status");
  // The settings: vdt_localizer3_defaults() (what this command always ran with), the keys of the
  // --config file's localize3d: section, then the flags given, which override the file.
  LocalizerSettings settings = cloud_settings();
  if (!a.config.empty()) {
    settings = load_localizer_config(a.config, settings);
    LocalizerSettings other = cloud_settings();
    other.vdt_opt = settings.vdt_opt;
    if (localizer_settings_yaml(other, "vdt-opt") !=
        localizer_settings_yaml(cloud_settings(), "vdt-opt")) {
      std::fprintf(stderr,
                   "[localize3d] note: %s sets vdt-opt (or sensor:) keys, which are `vdtnav "
                   "localize`'s; localize3d reads its own section, localize3d: (its optimizer: "
                   "has the vdt-opt keys)\n",
                   a.config.c_str());
    }
  }
  VdtLocalizer3Options& lo = settings.localize3d;
  if (a.min_explained_given) lo.accept_fraction = a.min_explained;
  if (a.multi_start) lo.multi_start.enabled = true;
  if (a.threads >= 0) settings.threads = a.threads;
  if (!std::isnan(a.attitude_sigma)) lo.held_attitude_sigma = a.attitude_sigma;
  lo.optimizer.four_dof = a.dof == 4;
  if (a.print_config) {
    std::fputs(localizer_settings_yaml(settings, "localize3d").c_str(), stdout);
    return;
  }
  apply_threads(a.threads, settings.threads);
  if (a.map.empty()) throw UsageError("localize3d: --map is required");
  if (!a.imu_csv.empty() && !a.imu_topic.empty())
    throw UsageError("localize3d: give --imu FILE or --imu-topic, not both");
  // The IMU's samples (sensor/imu.hpp): a CSV, or (below) a bag's Imu topic.
  std::vector<ImuSample> imu;
  if (!a.imu_csv.empty()) {
    ImuCsvReport report;
    imu = load_imu_csv(a.imu_csv, &report);
    if (imu.empty())
      throw FormatError(a.imu_csv, 0, "no IMU sample (expected rows t,wx,wy,wz,ax,ay,az)");
    const std::string dropped =
        report.non_finite_lines.empty()
            ? ""
            : ", " + std::to_string(report.non_finite_lines.size()) + " non-finite rows dropped";
    std::fprintf(stderr,
                 "[localize3d] IMU %s: %zu samples over [%.3f, %.3f] s%s, preintegrated between "
                 "scans (localize3d.imu)\n",
                 a.imu_csv.c_str(), imu.size(), imu.front().t, imu.back().t, dropped.c_str());
  }
  ImuMotion imu_motion(imu, lo.imu);
  std::size_t imu_steps = 0;
  const VdtOptimizerOptions& opt = lo.optimizer;
  const MultiStartOptions& ms = lo.multi_start;
  // --init global: the first scans are localized with no prior (global_localization3d.hpp) until
  // one is accepted; the tracker goes on from there.
  const bool init_global = a.init == "global";
  Pose3 init = Pose3::Identity();
  if (!a.init.empty() && !init_global) init = parse_pose3(a.init, "--init");
  if (!a.init_matrix.empty()) init = read_pose_matrix(a.init_matrix);
  MapLoadOptions mo = a.map_options;
  if (!a.quiet) mo.say = say_on_stderr("map3d");
  if (!a.crop.empty()) mo.crop = parse_crop_box(a.crop, "--crop");
  const std::vector<std::string> scans =
      !a.bag.empty() ? std::vector<std::string>{}
                     : (a.scans_dir.empty() ? a.scans : point_cloud_files_in(a.scans_dir));
  const bool sequence = scans.size() > 1 || !a.bag.empty();
  // The scans' stamps: --times (a line per scan), else their names' (stamp_of_name), else their
  // index.
  std::vector<double> stamps;
  if (!a.times.empty()) {
    if (!a.bag.empty())
      throw UsageError(
          "localize3d: --times is for --scan/--scans (a bag's clouds carry their stamps)");
    stamps = load_scan_times(a.times);
    if (stamps.size() != scans.size()) {
      throw FormatError(a.times, 0,
                        "expected a stamp per scan: " + std::to_string(stamps.size()) +
                            " stamps for " + std::to_string(scans.size()) + " scans");
    }
  }
  // --odom: the odometry's pose of each scan (KITTI: a line per cloud in name order; TUM: matched
  // to the clouds' name stamps, as map3d --poses reads them); the increment between consecutive
  // scans is the prediction, with the noise of the settings (localize3d.sigma_*).
  std::vector<Pose3> odom_poses;
  if (!a.odom.empty()) {
    if (!a.bag.empty())
      throw UsageError("localize3d: --odom is for --scan/--scans (a bag has --odom-topic)");
    odom_poses = poses_of_scans(load_scan_poses(a.odom), scans);
  }
  // The outputs appear when the run completes: a sequence's folder is written under a temporary
  // name beside it (staged_output.hpp), so a bad scan in the middle leaves nothing behind.
  StagedOutputs staged;
  std::string out_dir;
  if (sequence && !a.out.empty()) out_dir = staged.folder(a.out);

  std::fprintf(stderr, "[localize3d] map %s\n", a.map.c_str());
  const LoadedMap map = load_map(a.map, mo, 3);
  const VdtField3& field = map.field3();
  std::fprintf(stderr,
               "[localize3d] %s map %d x %d x %d voxels of %.3f m, %.0f MB, ready in %.2f s\n",
               map.source.c_str(), field.size().x(), field.size().y(), field.size().z(),
               field.resolution(), static_cast<double>(map.memory_bytes()) * 1e-6, map.seconds);
  const VdtOptimizer3 optimizer(field, opt);
  std::unique_ptr<GlobalLocalizer3> global;
  if (init_global) {
    const auto g0 = std::chrono::steady_clock::now();
    GlobalLocalization3Options go = lo.global;
    go.optimizer = opt;
    global = std::make_unique<GlobalLocalizer3>(field, go);
    const Eigen::Vector3i n = global->search_size();
    std::fprintf(stderr,
                 "[localize3d] --init global: %d x %d x %d search cells of %.2f m, %zu where the "
                 "sensor may be (%.2f m from the map's surfaces), ready in %.2f s\n",
                 n.x(), n.y(), n.z(), global->search_frame().resolution(), global->free_cells(),
                 go.clearance,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - g0).count());
  }
  CloudObservationOptions co;
  co.sigma_range = a.sigma_range;
  co.range_min = a.min_range;
  co.range_max = a.max_range;
  co.voxel = a.voxel >= 0.0 ? a.voxel : field.resolution();

  // The scans after the first go to the sequential 3D localizer (vdt_localizer3d.hpp): its
  // prediction is the last pose moved by the last motion (constant velocity, given as the
  // odometry), its acceptance and lost detection use the same explained fraction.
  RecoveringLocalizer3 tracker(optimizer, lo);  // lost detection and recovery around it
  std::vector<StampedPose3> trajectory;         // the poses of the accepted statuses
  std::vector<std::string> table = {status_table_header()};
  Pose3 last = init, before_last = init;
  double last_t = 0.0, before_last_t = 0.0;  // their stamps (constant velocity's dt)
  // Deskewing (sensor/sweep_motion.hpp): said once, from the first scan's time field.
  bool said_times = false;
  const auto say_times = [&](const std::string& field) {
    if (said_times || a.quiet) return;
    said_times = true;
    if (field.empty()) {
      std::fprintf(stderr,
                   "[localize3d] the clouds have no per-point time field (time, t, offset_time, "
                   "timestamp): each sweep is taken as instantaneous, not deskewed\n");
    } else {
      std::fprintf(stderr, "[localize3d] per-point times from field '%s': %s\n", field.c_str(),
                   lo.deskew ? "each sweep deskewed by the predicted motion"
                             : "not used (localize3d.deskew: false)");
    }
  };
  std::size_t accepted = 0, refused = 0, lost = 0;
  std::size_t count = 0;
  bool said_level = false;      // --init global without an IMU: said once
  std::vector<double> scan_ms;  // each scan's reading and solve: the summary's median, p99, max
  std::vector<double> scan_iterations;  // each scan's solver iterations (issue 57's counter)
  // One scan: solved from --init (or the prediction) until one is accepted, then tracked with the
  // motion given (odometry, and roll and pitch from an IMU) or constant velocity.
  const auto handle = [&](const std::string& name, double t, const ObservationSet3& obs,
                          std::size_t cloud_points, double read_ms,
                          const std::optional<OdometryStep3>& odometry) {
    ++count;
    ScanReport r;
    r.scan = name;
    const auto t1 = std::chrono::steady_clock::now();
    r.cloud_points = cloud_points;
    r.readings = obs.size();
    if (accepted == 0) {
      if (global) {  // --init global: no prior
        // Roll and pitch from the IMU: gravity over the 0.2 s before the scan (--imu, or a bag's
        // rates), else the bag's orientation (--imu-topic), else the sensor taken as level.
        double roll = 0.0, pitch = 0.0;
        bool imu = true;
        if (const std::optional<GravityAttitude> gravity = imu_motion.gravity(t, 0.2)) {
          roll = gravity->roll;
          pitch = gravity->pitch;
        } else if (odometry && odometry->has_attitude()) {
          roll = odometry->roll;
          pitch = odometry->pitch;
        } else {
          imu = false;
        }
        if (!imu && !said_level && !a.quiet) {
          said_level = true;
          std::fprintf(stderr,
                       "[localize3d] --init global: no IMU, roll and pitch searched from level "
                       "(the refinement frees them%s)\n",
                       a.dof == 4 ? "; --dof 4 holds them level" : "");
        }
        const GlobalLocalization3Result g = global->localize(obs, roll, pitch);
        r.result = g.result;
        if (!a.quiet) {
          const std::string why = g.ambiguous ? ", " + std::to_string(g.alternatives.size()) +
                                                    " distinct poses explain it as well"
                                              : "";
          std::fprintf(stderr,
                       "[localize3d] --init global, scan %zu: %s (%.0f %% explained%s), %zu "
                       "cubes in %.3f s\n",
                       count,
                       g.result.status == LocalizationStatus::kConverged ? "accepted"
                       : g.ambiguous                                     ? "refused, ambiguous"
                                                                         : "refused",
                       100.0 * g.explained, why.c_str(), g.nodes, g.seconds);
        }
      } else {  // from --init (or the prediction while nothing was accepted)
        // The guess moves with the odometry meanwhile (--odom, a bag's odometry).
        if (odometry && count > 1) last = last * odometry->delta;
        r.result = localize_from_guess(tracker.tracker(), obs, last);
      }
      r.explained = r.result.explained;
      if (r.result.status == LocalizationStatus::kConverged)
        tracker.reset(r.result.pose, r.result.covariance);
      if (a.dof == 4 && r.result.has_covariance) {  // the held roll and pitch (the file comment)
        r.result.covariance =
            tracker.tracker().with_held_attitude(obs, r.result, lo.held_attitude_sigma);
      }
    } else {
      OdometryStep3 motion;  // constant velocity unless the input has odometry
      motion.delta = before_last.inverse() * last;
      motion.dt = accepted > 1 ? last_t - before_last_t : 0.0;  // 0: no velocity known yet
      if (odometry) motion = *odometry;
      if (const std::optional<OdometryStep3> m = imu_motion.step(t)) {
        // The IMU's increment and covariance; roll and pitch: the bag's orientation, or in the
        // 4-DOF mode gravity's (held).
        const double roll = motion.roll, pitch = motion.pitch;
        motion = *m;
        motion.roll = roll;
        motion.pitch = pitch;
        if (a.dof == 4 && !motion.has_attitude()) {
          if (const std::optional<GravityAttitude> g = imu_motion.gravity(t, 0.2)) {
            motion.roll = g->roll;
            motion.pitch = g->pitch;
            motion.attitude_sigma = std::max(g->sigma_roll, g->sigma_pitch);
          }
        }
        ++imu_steps;
      }
      r.result = tracker.update(motion, obs);
      r.explained = r.result.explained;
      r.agreement = tracker.agreement();
    }
    if (r.agreement.readings == 0 && !obs.points.empty()) {  // solved alone: weighed here
      ScanAgreementOptions ao;
      ao.explained_distance = lo.explained_distance;
      r.agreement = scan_agreement(optimizer.sensor_model(), obs, r.result.pose, ao);
    }
    imu_motion.add(t, r.result.pose, r.result.covariance,
                   r.result.status == LocalizationStatus::kConverged);
    const auto t2 = std::chrono::steady_clock::now();
    r.read_ms = read_ms;
    r.solve_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
    scan_ms.push_back(read_ms + r.solve_ms);
    scan_iterations.push_back(static_cast<double>(r.result.iterations));
    if (r.result.status == LocalizationStatus::kConverged) {
      before_last = accepted == 0 ? r.result.pose : last;
      before_last_t = accepted == 0 ? t : last_t;
      last = r.result.pose;
      last_t = t;
      ++accepted;
    } else {
      ++refused;
    }
    lost += r.result.status == LocalizationStatus::kLost;
    const Eigen::Vector3d xyz = r.result.pose.translation();
    const Eigen::Vector3d rpy = rpy_of(r.result.pose.linear());
    std::printf(
        "%s: %s, %.0f %% explained, xyz %.3f %.3f %.3f m, rpy %.2f %.2f %.2f deg, sd %.3f m "
        "%.2f deg, %zu readings, %.1f ms\n",
        fs::path(name).filename().string().c_str(), to_string(r.result.status), 100.0 * r.explained,
        xyz.x(), xyz.y(), xyz.z(), rpy.x() * 180.0 / M_PI, rpy.y() * 180.0 / M_PI,
        rpy.z() * 180.0 / M_PI, std::sqrt(r.result.covariance.topLeftCorner<3, 3>().trace()),
        std::sqrt(r.result.covariance.bottomRightCorner<3, 3>().trace()) * 180.0 / M_PI, r.readings,
        r.solve_ms);
    if (r.result.status == LocalizationStatus::kRefused && !ms.enabled) {
      std::fprintf(stderr,
                   "[localize3d] %s: the map explains only %.0f %% of the scan at the estimate: "
                   "a wrong minimum or a poor guess; try --multi-start or a better --init\n",
                   name.c_str(), 100.0 * r.explained);
    }
    if (!a.out.empty()) {
      const std::string yaml =
          sequence ? (fs::path(out_dir) / (fs::path(name).stem().string() + ".yaml")).string()
                   : staged.file(a.out);
      write_text(yaml, yaml_report(r, a.dof, lo.explained_distance));
    }
    if (a.all_poses || accepted_statuses.count(r.result.status) > 0) {
      trajectory.push_back({t, r.result.pose});
    }
    table.push_back(status_row(t, r));
  };
  double previous_t = 0.0;  // the last scan's stamp (--odom's dt)
  for (std::size_t k = 0; k < scans.size(); ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    PointTimes times;
    const pcl::PointCloud<pcl::PointXYZ> cloud = read_point_cloud(scans[k], &times);
    if (times.absolute) {  // seconds after the scan's stamp: its name's (when it is a time of
      // this sweep, within 1 s of its readings), else its first reading's
      double first = std::numeric_limits<double>::infinity();
      for (const double t : times.seconds) first = std::min(first, t);
      const std::optional<double> named =
          stamps.empty() ? stamp_of_name(scans[k]) : std::optional<double>(stamps[k]);
      const double stamp = named && std::abs(*named - first) < 1.0 ? *named : first;
      for (double& t : times.seconds) t -= stamp;
    }
    say_times(times.field);
    const ObservationSet3 obs = observations_from_cloud(cloud, co, times.seconds);
    const double read_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const double t = stamps.empty() ? stamp_of(scans[k], k) : stamps[k];
    std::optional<OdometryStep3> odometry;
    if (!odom_poses.empty() && k > 0) {
      odometry = OdometryStep3{};
      odometry->delta = odom_poses[k - 1].inverse() * odom_poses[k];
      odometry->dt = std::max(t - previous_t, 1e-3);
    }
    previous_t = t;
    handle(scans[k], t, obs, cloud.size(), read_ms, odometry);
  }
#ifdef VDTNAV_CLI_ROS
  if (!a.bag.empty()) {
    const std::unique_ptr<ros::BagReader> bag = ros::BagReader::open(a.bag);
    ros::CloudSequenceOptions bo;
    bo.cloud_topic = a.cloud_topic;
    bo.odom_topic = a.odom_topic;
    bo.imu_topic = a.imu_topic;
    bo.odom_frame = a.odom_frame;
    bo.base_frame = a.base_frame;
    if (!a.lidar_pose.empty()) bo.lidar_pose = parse_pose3(a.lidar_pose, "--lidar-pose");
    std::optional<Pose3> previous_odometry;
    std::int64_t previous_stamp = 0;
    const ros::CloudSequenceInfo info =
        ros::read_cloud_sequence(*bag, bo, [&](const ros::CloudFrame& f) {
          const auto t0 = std::chrono::steady_clock::now();
          pcl::PointCloud<pcl::PointXYZ> cloud;
          cloud.reserve(f.cloud.points.size());
          for (const Eigen::Vector3d& p : f.cloud.points)
            cloud.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                          static_cast<float>(p.z())));
          if (f.imu != nullptr && imu.empty()) imu = *f.imu;  // the bag's rates, for ImuMotion
          CloudObservationOptions fo = co;
          fo.sensor_in_robot = f.mount;
          say_times(f.cloud.time_field);
          const ObservationSet3 obs = observations_from_cloud(cloud, fo, f.cloud.times);
          const double read_ms =
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                  .count();
          // The motion since the last cloud: the odometry's increment when there is odometry at
          // both stamps (else constant velocity), with the IMU's roll and pitch when there is an
          // IMU.
          std::optional<OdometryStep3> motion;
          if (f.odometry || std::isfinite(f.roll)) {
            OdometryStep3 m;
            m.delta = before_last.inverse() * last;
            if (f.odometry && previous_odometry)
              m.delta = previous_odometry->inverse() * *f.odometry;
            m.dt = 1e-9 * static_cast<double>(f.stamp_ns - previous_stamp);
            m.roll = f.roll;
            m.pitch = f.pitch;
            motion = m;
          }
          previous_odometry = f.odometry;
          previous_stamp = f.stamp_ns;
          char name[64];
          std::snprintf(name, sizeof name, "%.6f", 1e-9 * static_cast<double>(f.stamp_ns));
          handle(name, 1e-9 * static_cast<double>(f.stamp_ns), obs, f.cloud.points.size(), read_ms,
                 motion);
          return true;
        });
    std::fprintf(stderr, "[localize3d] %s: %zu clouds of %s, odometry %s, mounting %s%s%s\n",
                 a.bag.c_str(), count, info.cloud_topic.c_str(), info.odometry_source.c_str(),
                 info.mount_source.c_str(), info.imu_source.empty() ? "" : ", roll and pitch from ",
                 info.imu_source.c_str());
  }
#endif
  if (sequence && !a.out.empty()) {
    save_tum_trajectory((fs::path(out_dir) / "trajectory.tum").string(), trajectory);
    std::string csv;
    for (const std::string& row : table) csv += row + "\n";
    write_text((fs::path(out_dir) / "status.csv").string(), csv);
  }
  staged.commit();
  if (sequence && !a.out.empty()) {
    std::fprintf(stderr,
                 "[localize3d] wrote %s/trajectory.tum (%zu of %zu poses: %s), status.csv and one "
                 "YAML per scan\n",
                 a.out.c_str(), trajectory.size(), count,
                 a.all_poses ? "every status" : a.accept_status.c_str());
  }
  std::fprintf(stderr, "[localize3d] %zu scans: %zu converged, %zu not (%zu lost)\n", count,
               accepted, refused, lost);
  if (!imu.empty()) {
    std::fprintf(stderr,
                 "[localize3d] IMU: %zu of the %zu scans after the first predicted from it\n",
                 imu_steps, count - std::min<std::size_t>(count, 1));
    if (imu_steps == 0 && count > 1) {
      std::fprintf(stderr,
                   "[localize3d] warning: no scan interval lies within the IMU's samples [%.3f, "
                   "%.3f] s: the scans' stamps (from --times, their names, or their index) are "
                   "not on the IMU's time base; give --times FILE\n",
                   imu.front().t, imu.back().t);
    }
  }
  if (count > 0) {
    const eval::ErrorStatistics ms = eval::error_statistics(scan_ms);
    std::fprintf(stderr,
                 "[localize3d] ms per scan (reading the cloud and solving): %.3f mean, %.3f "
                 "median, %.3f p99, %.3f max\n",
                 ms.mean, ms.median, ms.p99, ms.max);
    const eval::ErrorStatistics it = eval::error_statistics(scan_iterations);
    std::fprintf(stderr,
                 "[localize3d] iterations per scan (every solve, coarse levels and multi-start "
                 "included): median %.0f, p99 %.0f\n",
                 it.median, it.p99);
  }
  if (accepted == 0 && init_global) {
    throw NotLocalized("localize3d: --init global: no scan of " + std::to_string(count) +
                       " found on the map with no prior (each unexplained anywhere, or ambiguous: "
                       "see above; wrong map, or a place that repeats)");
  }
  if (accepted == 0) {
    throw NotLocalized("localize3d: no scan of " + std::to_string(count) +
                       " localized (converged): the map does not explain them at the guess "
                       "(wrong map, --init, or try --multi-start)");
  }
  if (a.strict && lost > 0) {
    throw NotLocalized("--strict: " + std::to_string(lost) + " of " + std::to_string(count) +
                       " scans lost (the outputs are written)");
  }
}

}  // namespace

void add_localize3d_command(CLI::App& app) {
  auto args = std::make_shared<Localize3dArgs>();
  CLI::App* cmd = app.add_subcommand(
      "localize3d",
      "Localize 3D LiDAR scans on a 3D map: pose, 6x6 covariance and the fraction the map "
      "explains, per scan");
  cmd->add_option("--map", args->map,
                  "Map: point cloud (.pcd .ply .vtk .csv .txt .xyz), OctoMap (.bt .ot) or a map "
                  "saved by `vdtnav map3d` (.vdt dense, .svdt sparse); required")
      ->check(input_file("--map"));
  cmd->add_option("--scan", args->scans, "Scan file(s) (.pcd .ply .vtk .csv .txt .xyz), in order")
      ->check(input_file("--scan"));
  cmd->add_option("--scans", args->scans_dir, "A folder of scans, localized in name order");
#ifdef VDTNAV_CLI_ROS
  cmd->add_option("--bag", args->bag,
                  "ROS 1 bag (.bag) or ROS 2 bag folder: its sensor_msgs/PointCloud2 clouds, "
                  "localized in stamp order (a sequence: --out is a folder)")
      ->check(input_path("--bag"));
  cmd->add_option("--cloud-topic", args->cloud_topic,
                  "--bag: the PointCloud2 topic (default: the only one)");
  cmd->add_option("--odom-topic", args->odom_topic,
                  "--bag: a nav_msgs/Odometry topic, or 'none' (default: TF --odom-frame -> "
                  "--base-frame when the bag has it, else the only Odometry topic, else none: "
                  "constant velocity)");
  cmd->add_option("--imu-topic", args->imu_topic,
                  "--bag: a sensor_msgs/Imu topic: its orientation gives roll and pitch (the "
                  "4-DOF mode holds them), its rates and accelerations the prediction between "
                  "clouds (as --imu)");
  cmd->add_option("--odom-frame", args->odom_frame, "--bag: the odometry frame (REP 105)")
      ->capture_default_str();
  cmd->add_option("--base-frame", args->base_frame, "--bag: the robot's frame (REP 105)")
      ->capture_default_str();
  cmd->add_option("--lidar-pose", args->lidar_pose,
                  "--bag: the LiDAR's pose x,y,z,roll,pitch,yaw in --base-frame when the bag has "
                  "no transform to the clouds' frame");
#endif
  cmd->add_option("--imu", args->imu_csv,
                  "IMU samples as CSV t,wx,wy,wz,ax,ay,az (seconds on the scans' time base, "
                  "rad/s, m/s^2, robot frame): preintegrated between scans for the prediction and "
                  "its covariance (noise and biases: settings localize3d.imu); roll and pitch "
                  "from gravity for --init global and --dof 4")
      ->check(input_file("--imu"));
  cmd->add_option("--times", args->times,
                  "--scan/--scans: a stamp per scan in name order (seconds, one a line, as "
                  "KITTI's times.txt), for clouds whose names are not their stamps (default: the "
                  "names', else the index); the time base of --imu and deskewing")
      ->check(input_file("--times"));
  cmd->add_option("--odom", args->odom,
                  "--scan/--scans: the odometry's pose of each scan, KITTI (3x4 row-major, a line "
                  "per cloud in name order) or TUM (stamps matched to the clouds' names), as "
                  "map3d --poses reads them: the increments between scans are the prediction "
                  "(noise: settings localize3d.sigma_*)")
      ->check(input_file("--odom"));
  cmd->add_option("--init", args->init,
                  "Initial guess x,y,z,roll,pitch,yaw (metres, radians; default identity), or "
                  "'global': found from the first scans with no prior (branch and bound over "
                  "x, y, z, yaw; roll and pitch from --imu-topic, else level; settings section "
                  "localize3d.global)");
  cmd->add_option("--init-matrix", args->init_matrix,
                  "Initial guess as a 4x4 matrix file (16 numbers, row by row)");
  cmd->add_option("--dof", args->dof,
                  "6: full pose; 4: x, y, z, yaw (roll and pitch held at the guess's, e.g. from "
                  "an IMU)")
      ->capture_default_str();
  cmd->add_option("--resolution", args->map_options.resolution,
                  "Map voxel edge, metres (clouds: default 0.1; octrees: the tree's own)");
  cmd->add_option("--margin", args->map_options.margin,
                  "Free border around a cloud's or octree's occupied space, metres")
      ->capture_default_str();
  cmd->add_flag("--sparse", args->map_options.sparse,
                "Build a sparse map from a cloud or octree (bricks near the surfaces, no dense "
                "grid: building-sized maps; no coarse levels, so a poor guess needs "
                "--multi-start). A .svdt map is sparse anyway");
  cmd->add_flag("--thin-surfaces,!--no-thin-surfaces", args->map_options.thin_surfaces,
                "Clouds: thin each wall to the voxels its surface crosses (default), or keep every "
                "voxel with a point (a slab as thick as the points' scatter, in which a scan "
                "slides)");
  cmd->add_option("--crop", args->crop,
                  "Keep only the map cloud's points in the box xmin,ymin,zmin,xmax,ymax,zmax");
  cmd->add_option("--voxel", args->voxel,
                  "Scan downsampling, metres: one reading per cube (default: the map "
                  "resolution; 0: every reading)");
  cmd->add_option("--min-range", args->min_range, "Drop readings shorter than this, metres")
      ->capture_default_str();
  cmd->add_option("--max-range", args->max_range, "Drop readings at or beyond this, metres");
  cmd->add_option("--sigma-range", args->sigma_range,
                  "Range noise standard deviation of the sensor, metres")
      ->capture_default_str();
  cmd->add_option("--config", args->config,
                  "Settings YAML over the 3D defaults: its localize3d section (keys in "
                  "--print-config and docs/settings.md); the flags given override it")
      ->check(input_file("--config"));
  cmd->add_option("--out", args->out,
                  "One scan: a YAML file. A sequence: a folder (one YAML per scan, "
                  "trajectory.tum, status.csv: t,status,explained then the 6x6 covariance's "
                  "upper triangle, one row per scan)");
  CLI::Option* min_explained =
      cmd->add_option("--min-explained", args->min_explained,
                      "A converged pose explaining less of the scan is reported as refused "
                      "(localize3d.accept_fraction)")
          ->capture_default_str();
  cmd->add_flag("--multi-start", args->multi_start,
                "Solve again from starts around the guess when the first solution leaves "
                "readings unexplained (a poor guess)");
  cmd->add_option("--attitude-sigma", args->attitude_sigma,
                  "--dof 4: the standard deviation of the held roll and pitch (from --init), "
                  "radians. Unset: they are not estimated, NaN in the covariance");
  add_pose_selection_options(*cmd, args->all_poses, args->accept_status,
                             "A sequence's trajectory.tum", "status.csv");
  cmd->add_flag("--strict", args->strict, "Exit 3 when a scan of the sequence is lost");
  cmd->add_flag("--quiet", args->quiet, "Less on stderr");
  add_threads_option(*cmd, args->threads);
  cmd->add_flag("--print-config", args->print_config,
                "Print the settings in use (defaults + --config + the flags given), the "
                "localize3d section, as a documented YAML and exit");
  cmd->callback([args, min_explained] {
    args->min_explained_given = min_explained->count() > 0;
    run_localize3d(*args);
  });
}

}  // namespace vdtnav::tools
