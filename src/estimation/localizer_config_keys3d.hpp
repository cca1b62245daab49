#pragma once
// The keys of the settings file's localize3d: section (private to the estimation component): the
// sequential 3D localizer of `vdtnav localize3d` (VdtLocalizer3Options, vdt_localizer3d.hpp), as
// localizer_config_keys.hpp names the 2D ones. Its optimizer reuses the vdt-opt keys; the 4-DOF
// mode is not a key (--dof chooses it).

#include "localizer_config_keys.hpp"
#include "vdtnav/estimation/global_localization3d.hpp"
#include "vdtnav/estimation/multi_start.hpp"
#include "vdtnav/estimation/vdt_localizer3d.hpp"

namespace vdtnav::config_keys {

template <typename V>
void visit(V& v, MultiStartOptions& o) {
  v.flag("enabled", o.enabled,
         "solve again from starts around the guess while the solution explains less than "
         "accept_fraction (--multi-start turns it on)");
  v.number("explained_distance", o.explained_distance, "m",
           "a reading with |d| below this is explained");
  v.number("accept_fraction", o.accept_fraction, "fraction",
           "stop once a solution explains this fraction of the readings");
  v.number("offset_translation", o.offset_translation, "m",
           "starts this far from the guess along x, y, z");
  v.number("offset_rotation", o.offset_rotation, "rad",
           "starts turned this much about x, y, z (4-DOF: about z)");
  v.number("truncation", o.truncation, "m", "tau of the truncated VCD that scores the solutions");
  v.size("all_starts_below", o.all_starts_below, "count",
         "sets with fewer readings try every start, then the hops");
  v.integer("hops", o.hops, "count",
            "starts drawn within +-offset of the best so far (sets under all_starts_below)");
  v.uint32("hop_seed", o.hop_seed, "-", "random seed of the hops");
  v.integer("attitude_grid", o.attitude_grid, "count",
            "n of the last stage: the attitudes Exp(step (i, j, k)) R_guess, i, j, k in [-n, n] "
            "(4-DOF: yaw only); 0: off");
  v.number("attitude_grid_step", o.attitude_grid_step, "rad", "step of the attitude grid");
  v.size("screen_readings", o.screen_readings, "count",
         "the grid's attitudes are solved and scored on this many readings first");
  v.integer("screen_keep", o.screen_keep, "count",
            "the best screened attitudes, solved with every reading");
}

template <typename V>
void visit(V& v, ImuNoise& o) {
  v.number("gyro_noise_density", o.gyro_noise_density, "rad/s/sqrt(Hz)",
           "gyro white noise (default: the Bosch BMI088's data sheet, 0.014 deg/s/sqrt(Hz))");
  v.number("accel_noise_density", o.accel_noise_density, "m/s^2/sqrt(Hz)",
           "accelerometer white noise (BMI088: 175 ug/sqrt(Hz))");
  v.number("gyro_bias_x", o.gyro_bias.x(), "rad/s", "known gyro bias, subtracted (x axis)");
  v.number("gyro_bias_y", o.gyro_bias.y(), "rad/s", "known gyro bias, subtracted (y axis)");
  v.number("gyro_bias_z", o.gyro_bias.z(), "rad/s", "known gyro bias, subtracted (z axis)");
  v.number("accel_bias_x", o.accel_bias.x(), "m/s^2", "known accelerometer bias, subtracted");
  v.number("accel_bias_y", o.accel_bias.y(), "m/s^2", "known accelerometer bias, subtracted");
  v.number("accel_bias_z", o.accel_bias.z(), "m/s^2", "known accelerometer bias, subtracted");
  v.number("gyro_bias_sigma", o.gyro_bias_sigma, "rad/s",
           "1 sigma per axis of the gyro bias left after subtraction (constant over a window)");
  v.number("accel_bias_sigma", o.accel_bias_sigma, "m/s^2",
           "1 sigma per axis of the accelerometer bias left after subtraction");
  v.number("gravity", o.gravity, "m/s^2", "magnitude of gravity");
}

template <typename V>
void visit(V& v, GlobalLocalization3Options& o) {
  v.number("truncation", o.truncation, "m", "tau: a reading farther from the map counts tau^2");
  v.integer("max_readings", o.max_readings, "count", "readings scored, evenly over the scan");
  v.number("resolution", o.resolution, "m",
           "the search grid's edge; <= 0: the map's, at least 0.1 m and at most 2^25 cells");
  v.number("angular_step", o.angular_step, "rad",
           "between headings; <= 0: the edge / the scan's 90th-percentile range, in [0.5, 3] "
           "degrees");
  v.integer("levels", o.levels, "count", "coarsest cube 2^levels cells; < 0: about 3.2 m");
  v.number("clearance", o.clearance, "m", "the sensor is not placed nearer the map's surfaces");
  v.number_or_nan("min_z", o.min_z, "m",
                  "lowest sensor height searched (map frame); .nan: no bound");
  v.number_or_nan("max_z", o.max_z, "m", "highest sensor height searched; .nan: no bound");
  v.size("max_nodes", o.max_nodes, "count",
         "cubes scored at most; a search that reaches it decides on the leaves it has");
  visit_global_decision(v, o);
}

template <typename V>
void visit(V& v, VdtLocalizer3Options& o) {
  v.section("optimizer",
            "the 6-DOF (--dof 4: 4-DOF) solve, keys of vdt-opt (search and bridge are 2D "
            "only); its sensor: is the 3D map's, the top-level sensor: block does not reach it",
            [&](V& s) { visit(s, o.optimizer); });
  v.number("sigma_translation_per_metre", o.sigma_translation_per_metre, "m/m",
           "odometry noise (1 sigma, robot frame) per metre travelled in an increment");
  v.number("sigma_rotation_per_radian", o.sigma_rotation_per_radian, "rad/rad",
           "odometry noise per radian turned in an increment");
  v.number("sigma_translation_per_second", o.sigma_translation_per_second, "m/s",
           "odometry noise per second (a robot standing still drifts too)");
  v.number("sigma_rotation_per_second", o.sigma_rotation_per_second, "rad/s",
           "odometry rotation noise per second");
  v.number("sigma_imu_attitude", o.sigma_imu_attitude, "rad",
           "the IMU's roll and pitch noise (1 sigma), for odometry that carries them");
  v.section("imu",
            "the IMU's rates and specific forces (--imu FILE.csv, or a bag's --imu-topic), "
            "preintegrated between scans into the prediction and its covariance (sensor/imu.hpp)",
            [&](V& s) { visit(s, o.imu); });
  v.flag("deskew", o.deskew,
         "move readings that carry times (a spinning LiDAR's sweep) to the scan's stamp by the "
         "predicted motion, then by the motion to the solution (sensor/sweep_motion.hpp); "
         "false: scans are instantaneous");
  v.integer("deskew_passes", o.deskew_passes, "count",
            "solves per deskewed scan: the first by the predicted motion, the next by the motion "
            "to the last solution, until it settles within 1 mm over the sweep");
  v.number_or_nan("held_attitude_sigma", o.held_attitude_sigma, "rad",
                  "4-DOF without an IMU: the held roll and pitch's standard deviation "
                  "(--attitude-sigma); .nan: not estimated (NaN rows and columns in the "
                  "covariance)");
  v.number("explained_distance", o.explained_distance, "m",
           "a reading with a smaller disparity is explained (acceptance, lost detection)");
  v.number("accept_fraction", o.accept_fraction, "fraction",
           "refuse a solution explaining less of the scan (after multi-start); --min-explained");
  v.section("multi_start", "starts around the prediction for a solution that explains too little",
            [&](V& s) { visit(s, o.multi_start); });
  v.section("lost",
            "lost detection over a window of scans (keys of recovery:); in 3D every reading the "
            "map does not explain counts as a contradiction",
            [&](V& s) { visit(s, o.lost); });
  v.flag("global_recovery", o.global_recovery,
         "while lost, also search the whole map (global:) on the re-acquiring scans, and adopt a "
         "pose it accepts");
  v.section("global",
            "global localization from one scan (branch and bound over x, y, z, yaw; roll and "
            "pitch from the IMU or level), --init global and recovery; refines with optimizer:",
            [&](V& s) { visit(s, o.global); });
}

}  // namespace vdtnav::config_keys
