#pragma once
/// \file
/// \brief The figures the tool writes: trajectories over the map, scans reprojected from the
/// estimated poses (thesis Figs. 3.6-3.11), and errors over time.

#include <string>
#include <vector>

#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/sensor/laser_scan.hpp"

namespace vdtnav::tools {

/// \return whether this build draws figures (vdtnav::viz, which needs OpenCV, was built).
/// Without it (plots_without_viz.cpp) every plot_ function throws ConfigError; the commands
/// refuse --plot when they parse it, with plot_option_check().
[[nodiscard]] bool plots_available();

/// \return "" when plots_available(), else the reason --plot cannot be given (a CLI11 check).
[[nodiscard]] inline std::string plot_option_check(const std::string& /*prefix*/) {
  return plots_available() ? std::string()
                           : std::string(
                                 "--plot needs OpenCV, and this vdtnav was built without "
                                 "it (install libopencv-dev and rebuild)");
}

/// \brief One trajectory to draw.
struct PlotTrack {
  std::string label;
  std::vector<Pose2> poses;
  bool dashed = false;
};

/// \brief Trajectories over the map, with a heading marker every `every` poses of the first.
void plot_trajectories(const std::string& png, const RosMap& map,
                       const std::vector<PlotTrack>& tracks, const std::string& title,
                       int every = 15);

/// \brief Every scan's endpoints drawn from its estimated pose over the map: a sharp overlay means
/// the poses are right.
void plot_reprojected_scans(const std::string& png, const RosMap& map,
                            const std::vector<Pose2>& poses, const std::vector<LaserScan>& scans,
                            const std::string& title);

/// \brief Per-component error over time (x, y, yaw), with +-2 sigma bands when given.
void plot_errors(const std::string& png, const std::vector<double>& t,
                 const std::vector<Eigen::Vector3d>& error,
                 const std::vector<Eigen::Vector3d>& two_sigma, const std::string& title);

}  // namespace vdtnav::tools
