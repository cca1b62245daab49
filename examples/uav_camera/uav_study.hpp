#pragma once
// The machinery of the UAV downward-camera study (uav_camera.cpp): the scenario — camera, scene,
// marking map and flight (flight_scenario.cpp) —, the localizers' run over the flight
// (flight_localization.cpp), the table (study_table.cpp) and the figures (study_figures.cpp).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "vdtnav/camera_sim/runway_scene.hpp"
#include "vdtnav/camera_sim/uav_flight.hpp"
#include "vdtnav/core/pose2.hpp"
#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/uav_camera/camera_model.hpp"
#include "vdtnav/uav_camera/uav_camera_front_end.hpp"
#include "vdtnav/uav_camera/uav_rig.hpp"

namespace uav_study {

constexpr double kPi = 3.14159265358979323846;

/// One method's run over the flight.
struct Trace {
  std::string name;
  std::vector<vdtnav::Pose2> estimate;
  std::vector<Eigen::Matrix3d> covariance;
  std::vector<char> has_cov;
  std::vector<vdtnav::LocalizationStatus> status;
  std::vector<int> iterations;
  double ms = 0.0;               // localizer time, all frames
  std::vector<double> frame_ms;  // each frame's localizer time (the table adds the front end's)
};

/// What the study flies over and how: the camera, the scene, the marking map it localizes on
/// and the simulated flight.
struct Scenario {
  vdtnav::uav_camera::CameraCalibration calibration;
  vdtnav::uav_camera::UavRig rig;
  vdtnav::uav_camera::RunwayScene scene;
  vdtnav::OccupancyGrid<2> boundaries;  ///< the map's boundary cells
  vdtnav::VdtMap2 map;
  vdtnav::uav_camera::UavFlightOptions fo;  ///< the flight's options (its sensors' noise)
  std::vector<vdtnav::uav_camera::UavFlightSample> flight;
};

/// The runway with its figure-of-eight road (or `texture_path`'s photograph laid on the ground
/// when not empty), its marking map (written to out/map.png + map.yaml and read back) and the
/// flight of `frames` frames around `altitude`; prints what it made.
Scenario make_scenario(const std::string& out, std::uint64_t seed, std::size_t frames,
                       double altitude, const std::string& texture_path);

/// The three localizers' run over the flight, and what the table and figures need of it.
struct FlightRun {
  std::vector<Trace> traces;  ///< vdt-opt, vdt-ekf, udt-opt
  /// Per frame: 1 when it sees the road (min_explained edge points explained at the true pose).
  std::vector<char> features;
  std::vector<double> front_ms;  ///< per frame: the front end's time
  int min_explained = 0;
  std::size_t shown = 0;  ///< the frame drawn in frame.png
  cv::Mat shown_image;
  vdtnav::uav_camera::CameraFrame shown_frame;
};

/// Renders every frame of the flight, extracts its edges and runs vdt-opt, vdt-ekf and udt-opt
/// on them side by side (`solver`: vdt-opt's scan solver, "default", "dense" or "ceres").
FlightRun localize_flight(const Scenario& sc, double altitude, const std::string& solver,
                          std::uint64_t seed, bool verbose);

/// Writes out/table.csv and out/table.md and prints the table and the statuses.
void write_tables(const std::string& out, const Scenario& sc, const FlightRun& run);

/// Writes trajectory.png (Fig. 3.13), errors_vdt_opt.png and errors_vdt_ekf.png (Fig. 3.14) and
/// frame.png in `out`.
void draw_figures(const std::string& out, const Scenario& sc, double altitude,
                  const FlightRun& run);

}  // namespace uav_study
