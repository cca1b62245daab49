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
