// The study on a real sequence (--scans DIR --poses FILE): the odd scans (1, 3, 5, ..., counted
// from 0 in name order) registered at their reference poses make the map, as
// `vdtnav map3d --scans DIR --poses FILE --skip-even` makes it (merged, 0.1 m voxels by default,
// walls thinned); the even scans are localized on it in order by what `vdtnav localize3d` runs
// (vdt_localizer3_defaults(), in RecoveringLocalizer3), 6-DOF and 4-DOF, each
// predicted by an odometry increment drawn from the reference poses with the simulated drive's
// noise (VdtLocalizer3Options::noisy_odometry: 5 % per metre + 0.02 m/s, 5 % per radian +
// 0.01 rad/s, and an IMU's roll and pitch for the 4-DOF run), the first from its reference moved
// by N(0, 5 cm) per axis and N(0, 0.02 rad) per angle. The reference is what the pose file
// says (a SLAM or GNSS/INS estimate, not ground truth). table.csv has the simulated drive's
// columns; table.md says the sequence and the map; <method>.tum holds each run's estimates.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "lidar_3d_study.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/estimation/recovering_localizer3d.hpp"
#include "vdtnav/estimation/scan_agreement.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/io/scan_run.hpp"
#include "vdtnav/io/tum_trajectory.hpp"
#include "vdtnav/map/sparse_vdt_map.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/pcl/cloud_observations.hpp"
#include "vdtnav/pcl/point_cloud_conversion.hpp"
#include "vdtnav/pcl/point_cloud_file.hpp"
#include "vdtnav/pcl/registered_scans.hpp"

namespace lidar3d {

using namespace vdtnav;
using Clock = std::chrono::steady_clock;

/// Voxels of the largest dense map the study builds (2 GB of VDT); beyond, a sparse map.
constexpr double kMaxDenseVoxels = 134217728.0;  // 2^27

/// Metres by which the agreement table moves each scan off its reference (a kidnapped track).
constexpr double kOffMetres = 5.0;

/// What the map says of each localized scan at its reference pose and 5 m off it (forward, back,
/// left, right in the scan's frame): agreement.csv, a row per scan and pose, and a summary line in
/// table.md — the evidence lost detection weighs (scan_agreement.hpp), on this sequence.
void write_agreement(const std::string& out, std::ostream& md, const VdtSensorModel3& model,
                     const std::vector<ObservationSet3>& scans, const std::vector<Pose3>& truth,
                     double explained_distance) {
  std::ofstream csv(out + "/agreement.csv");
  csv << "scan,offset_m,direction,readings,explained,contradicted,unknown,explained_fraction,"
         "contradiction\n";
  ScanAgreementOptions ao;
  ao.explained_distance = explained_distance;
  std::vector<double> ref_c, off_c, ref_e, off_e;
  const Eigen::Vector3d dirs[4] = {Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitX(),
                                   Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitY()};
  for (std::size_t i = 0; i < scans.size(); ++i) {
    for (int k = -1; k < 4; ++k) {
      Pose3 at = truth[i];
      if (k >= 0) at.translation() += truth[i].linear() * (kOffMetres * dirs[k]);
      const ScanAgreement a = scan_agreement(model, scans[i], at, ao);
      char line[256];
      std::snprintf(line, sizeof line, "%zu,%.1f,%d,%d,%d,%d,%d,%.4f,%.4f\n", i,
                    k < 0 ? 0.0 : kOffMetres, k, a.readings, a.explained, a.contradicted, a.unknown,
                    a.explained_fraction(), a.contradiction());
      csv << line;
      (k < 0 ? ref_c : off_c).push_back(a.contradiction());
      (k < 0 ? ref_e : off_e).push_back(a.explained_fraction());
    }
  }
  const auto quantile = [](std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
  };
  char line[512];
  std::snprintf(line, sizeof line,
                "\nWhat the map says of each scan (agreement.csv; scan_agreement.hpp): at the "
                "reference, explained %.2f (median; min %.2f), contradiction C/(E+C) %.2f "
                "(median; max %.2f); %.0f m off (4 directions), explained %.2f (median; max %.2f), "
                "contradiction %.2f (median; min %.2f).\n",
                quantile(ref_e, 0.5), quantile(ref_e, 0.0), quantile(ref_c, 0.5),
                quantile(ref_c, 1.0), kOffMetres, quantile(off_e, 0.5), quantile(off_e, 1.0),
                quantile(off_c, 0.5), quantile(off_c, 0.0));
  md << line;
  std::fputs(line + 1, stdout);
}

void run_real_scans(const RealScans& o) {
  const std::vector<std::string> clouds = point_cloud_files_in(o.dir);
  const ScanPoseFile pose_file = load_scan_poses(o.poses);
  const std::vector<Pose3> reference = poses_of_scans(pose_file, clouds);
  const std::vector<Pose3> odometry =
      o.odom.empty() ? std::vector<Pose3>{} : poses_of_scans(load_scan_poses(o.odom), clouds);
  VDTNAV_CHECK(clouds.size() >= 2, o.dir +
                                       ": a real sequence needs two scans or more (the odd "
                                       "ones make the map, the even ones are localized)");
  const std::vector<std::size_t> map_scans = select_scans(clouds.size(), {1, false, true});
  const std::vector<std::size_t> loc_scans = select_scans(clouds.size(), {1, true, false});
  std::vector<std::string> map_files;
  std::vector<Pose3> map_poses;
  for (const std::size_t k : map_scans) {
    map_files.push_back(clouds[k]);
    map_poses.push_back(reference[k]);
  }
  const auto m0 = Clock::now();
  const pcl::PointCloud<pcl::PointXYZ> merged =
      merge_scan_files(map_files, map_poses, o.resolution / 4.0);
  PointCloudOccupancyOptions mo;
  mo.resolution = o.resolution;
  mo.margin = 1.0;  // map3d's default
  // A dense grid over the merged cloud's box, unless that would pass kMaxDenseVoxels: then the
  // sparse map (bricks near the surfaces; what `map3d --out X.svdt` builds).
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
  for (const pcl::PointXYZ& p : merged) {
    lo = lo.cwiseMin(p.getVector3fMap());
    hi = hi.cwiseMax(p.getVector3fMap());
  }
  const Eigen::Vector3d cells =
      ((hi - lo).cast<double>().array() + 2.0 * mo.margin) / o.resolution + 1.0;
  const bool sparse = cells.prod() > kMaxDenseVoxels;
  std::unique_ptr<VdtField3> map;
  if (sparse) {
    map = std::make_unique<SparseVdtMap3>(sparse_vdt_map_from_point_cloud(merged, mo));
  } else {
    map =
        std::make_unique<VdtMap3>(VdtMap3::build(occupancy_from_point_cloud(merged, mo).occupancy));
  }
  std::fprintf(stderr,
               "[lidar_3d] %s map of the %zu odd scans of %s: %.0f x %.0f x %.0f voxels of %.3f m "
               "(%.1f s)\n",
               sparse ? "sparse" : "dense", map_files.size(), o.dir.c_str(), cells.x(), cells.y(),
               cells.z(), o.resolution, std::chrono::duration<double>(Clock::now() - m0).count());

  VdtLocalizer3Options o6 = vdt_localizer3_defaults();
  // A sparse map has no coarse levels to widen the basin: the scans solved alone (until one is
  // accepted) start from around the guess too (`localize3d --multi-start`); on libpointmatcher's
  // car pair, a start 2.2 deg off in yaw otherwise stops 1.3 deg off.
  o6.multi_start.enabled = sparse;
  VdtLocalizer3Options o4 = o6;
  o4.optimizer.four_dof = true;
  RecoveringLocalizer3 loc6(*map, o6);
  RecoveringLocalizer3 loc4(loc6.tracker().optimizer(), o4);  // the same pyramid
  RecoveringLocalizer3* locs[2] = {&loc6, &loc4};
  Run runs[2];
  Matrix6d p0 = Matrix6d::Zero();
  p0.diagonal() << 0.05 * 0.05, 0.05 * 0.05, 0.05 * 0.05, 0.02 * 0.02, 0.02 * 0.02, 0.02 * 0.02;
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  Vector6d start_error;
  for (int k = 0; k < 6; ++k) start_error[k] = std::sqrt(p0(k, k)) * n01(rng);
  const Pose3 start = oplus(reference[loc_scans.front()], start_error);
  // What `vdtnav localize3d` does (cmd_localize3d.cpp): a scan is solved alone from the guess
  // (localize_from_guess) until one is accepted, which starts the tracker; the guess moves with
  // the odometry meanwhile. The 4-DOF guess holds the IMU's roll and pitch.
  Pose3 guess[2] = {start, start};
  bool tracking[2] = {false, false};
  for (int m = 0; m < 2; ++m) runs[m].name = locs[m]->name() + "-real";
  // A scan's time: its name with TUM poses (matched to it), else 0.1 s per scan (10 Hz; KITTI's
  // 000042.pcd is a frame number, not a time).
  const auto time_of = [&](std::size_t k) {
    return pose_file.format == ScanPoseFormat::kTum ? *stamp_of_name(clouds[k])
                                                    : 0.1 * static_cast<double>(k);
  };
  std::vector<Pose3> truth;
  std::vector<ObservationSet3> localized;  // for the agreement table
  double voxel = o.voxel;
  std::size_t readings_sum = 0;
  for (std::size_t i = 0; i < loc_scans.size(); ++i) {
    const std::size_t k = loc_scans[i];
    const pcl::PointCloud<pcl::PointXYZ> cloud = read_point_cloud(clouds[k]);
    if (voxel < 0.0) voxel = o.points > 0 ? voxel_for(cloud, o.points) : o.resolution;
    CloudObservationOptions co;
    co.sigma_range = o.sigma_range;
    co.voxel = voxel;
    const ObservationSet3 obs = observations_from_cloud(cloud, co);
    readings_sum += obs.size();
    localized.push_back(obs);
    const std::size_t prev = i == 0 ? k : loc_scans[i - 1];
    // The first scan's "increment" is none, with the IMU's roll and pitch.
    const double dt = i == 0 ? 0.1 : std::max(time_of(k) - time_of(prev), 1e-3);
    OdometryStep3 odo;
    if (odometry.empty()) {
      odo = o6.noisy_odometry(reference[prev], reference[k], dt, rng);
    } else {  // --odom: the file's increment, the settings' noise; no IMU attitude
      odo.dt = dt;
      odo.delta = odometry[prev].inverse() * odometry[k];
    }
    truth.push_back(reference[k]);
    for (int m = 0; m < 2; ++m) {
      const auto s0 = Clock::now();
      LocalizationResult3 r;
      if (tracking[m]) {
        r = locs[m]->update(odo, obs);
      } else {
        if (i > 0) guess[m] = guess[m] * odo.delta;
        if (m == 1 && odo.has_attitude()) {  // roll and pitch from the IMU
          const Eigen::Vector3d rpy = rpy_of(guess[m].linear());
          const Eigen::Vector3d t = guess[m].translation();
          guess[m] = pose3_from_xyz_rpy(t.x(), t.y(), t.z(), odo.roll, odo.pitch, rpy.z());
        }
        r = localize_from_guess(locs[m]->tracker(), obs, guess[m]);
        if (m == 1 && r.has_covariance)
          r.covariance = locs[m]->tracker().with_held_attitude(obs, r, o4.sigma_imu_attitude);
        if (r.status == LocalizationStatus::kConverged) {
          locs[m]->reset(r.pose, r.covariance);
          tracking[m] = true;
        }
      }
      runs[m].record(r, reference[k], std::chrono::duration<double>(Clock::now() - s0).count());
    }
  }

  // Each run's estimates, stamped as the scans (for evo and the like).
  for (const Run& r : runs) {
    std::vector<StampedPose3> poses;
    for (std::size_t i = 0; i < loc_scans.size(); ++i)
      poses.push_back({time_of(loc_scans[i]), r.estimates[i]});
    save_tum_trajectory(o.out + "/" + r.name + ".tum", poses);
  }
  std::ofstream csv(o.out + "/table.csv");
  std::ofstream md(o.out + "/table.md");
  md << "# 3D LiDAR localization on a real sequence: " << o.dir << "\n\n"
     << "The " << map_files.size() << " odd scans (counted from 0 in name order) registered at "
     << "their reference poses (" << o.poses << ") make the map (" << o.resolution
     << " m voxels, walls thinned, as `vdtnav map3d --scans --skip-even` does"
     << (sparse ? ", a sparse map: its dense grid would pass 2^27 voxels" : "") << "); the "
     << loc_scans.size() << " even scans are localized on it in order with `vdtnav localize3d`'s "
     << "settings, about " << readings_sum / loc_scans.size() << " readings per scan after "
     << voxel << " m voxel downsampling, each predicted by "
     << (o.odom.empty()
             ? "odometry drawn from the reference with 5 % per metre + 0.02 m/s, 5 % per radian + "
               "0.01 rad/s of noise (the 4-DOF run: an IMU's roll and pitch, sigma " +
                   std::to_string(o6.sigma_imu_attitude) + " rad)"
             : "the increments of the odometry " + o.odom +
                   " (the settings' odometry noise; the "
                   "4-DOF run holds the prediction's roll and pitch)")
     << ". Errors and NEES are against the reference, which is an estimate, not ground "
        "truth. ANEES interval: 95 % (chi-square, N x dof).\n\n";
  write_rows(csv, md, truth, runs, 2);
  md << "\nTimes: localizer update per scan (observations given), this machine.\n";
  write_agreement(o.out, md, loc6.tracker().optimizer().sensor_model(), localized, truth,
                  o6.explained_distance);
}

}  // namespace lidar3d
