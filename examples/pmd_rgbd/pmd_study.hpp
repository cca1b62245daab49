#pragma once
// The machinery of the PMD study (pmd_rgbd.cpp): the park, its map and the drive
// (park_scenario.cpp), the four filters' run over the drive (filter_run.cpp), the table
// (study_table.cpp), the figures (study_figures.cpp), and the relative localization between
// recorded Kinect frames (kinect_study.cpp).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "vdtnav/camera_sim/park_scene.hpp"
#include "vdtnav/camera_sim/scooter_drive.hpp"
#include "vdtnav/core/pose2.hpp"
#include "vdtnav/estimation/bearing_update.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/rgbd_ground/ground_boundaries.hpp"

namespace pmd_study {

/// One filter's run over the drive.
struct Trace {
  std::string name;
  std::vector<vdtnav::Pose2> estimate;
  std::vector<Eigen::Matrix3d> covariance;
  double ms = 0.0;  // filter time over all frames (front end excluded)
  bool uses_frames = false;
  std::vector<double> frame_ms;  // each frame's time, the front end's included when it uses it
  int refused = 0;  // frames whose boundary update the filter refused (prediction only)
};

/// The generated park, its boundary map and the scooter's drive through it.
struct Scenario {
  vdtnav::rgbd_ground::ParkScene scene;
  double resolution = 0.0;              ///< of the map, metres
  vdtnav::OccupancyGrid<2> boundaries;  ///< the map's boundary cells
  vdtnav::VdtMap2 map;
  vdtnav::rgbd_ground::ScooterDriveOptions dopt;
  vdtnav::rgbd_ground::ScooterDrive drive;
  std::size_t n = 0;  ///< frames to run
};

/// The park of `seed`, its map and the drive (`frames` > 0: only its first frames); prints them.
Scenario make_scenario(std::uint64_t seed, std::size_t frames);

/// The four filters' run over the drive, and what the table and figures need of it.
struct FilterRun {
  std::vector<Trace> traces;  ///< vdt-ekf, vdt-ekf+bearings, bearings, odometry
  double front_ms = 0.0;      ///< the front end's mean time per frame
  std::vector<vdtnav::Landmark2> landmarks;
  std::size_t shown = 0;  ///< the frame drawn in frame.png
  cv::Mat shown_colour;
  vdtnav::rgbd_ground::GroundBoundaries shown_boundaries;
};

/// Renders every frame of the drive, extracts its ground boundaries and landmark bearings and
/// runs the four filters side by side (`correlation_length`, `schmidt`: the map errors' model;
/// `correction_gate`: VdtEkfOptions::correction_gate of both VDT filters).
FilterRun run_filters(const Scenario& sc, double correlation_length, bool schmidt,
                      double correction_gate, std::uint64_t seed, bool verbose);

/// Writes out/table.csv and out/table.md and prints the table.
void write_tables(const std::string& out, const Scenario& sc, const FilterRun& run);

/// Writes trajectories.png (Fig. 3.24), errors.png (Fig. 3.23) and frame.png in `out`.
void draw_figures(const std::string& out, const Scenario& sc, const FilterRun& run);

/// Relative localization between recorded frames (issue 13, item 5). The camera is hand-held:
/// its robot frame is the floor under it (x forward, y left), with roll, pitch and height from
/// the fitted floor (levelled_extrinsics) and the given pose's yaw and position. Each frame's
/// boundary points are localized by vdt-opt on a 2 cm VDT map of the other frames' points, drawn
/// through the given poses (robot frame of frame 1), from the given pose and from 4 cm, 3 cm and
/// 1 degree off; the errors are against the given poses (a reference with centimetres of error of
/// its own: 3-10 cm of depth disagreement between frames warped through them).
/// `calibration`: an OpenCV or ROS calibration file; empty: the Kinect v1 intrinsics the data's
/// README gives for ../shared/data/vision/rgbd-kinect (no distortion).
int kinect_study(const std::string& dir, const std::string& calibration, const std::string& out);

}  // namespace pmd_study
