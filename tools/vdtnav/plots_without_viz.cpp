// The figures of plots.hpp in a vdtnav built without OpenCV (so without vdtnav::viz): none. The
// commands refuse --plot when they parse it (plot_option_check); a direct call says why.
#include <string>
#include <vector>

#include "plots.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::tools {

bool plots_available() { return false; }

void plot_trajectories(const std::string& /*png*/, const RosMap& /*map*/,
                       const std::vector<PlotTrack>& /*tracks*/, const std::string& /*title*/,
                       int /*every*/) {
  throw ConfigError(plot_option_check(""));
}

void plot_reprojected_scans(const std::string& /*png*/, const RosMap& /*map*/,
                            const std::vector<Pose2>& /*poses*/,
                            const std::vector<LaserScan>& /*scans*/, const std::string& /*title*/) {
  throw ConfigError(plot_option_check(""));
}

void plot_errors(const std::string& /*png*/, const std::vector<double>& /*t*/,
                 const std::vector<Eigen::Vector3d>& /*error*/,
                 const std::vector<Eigen::Vector3d>& /*two_sigma*/, const std::string& /*title*/) {
  throw ConfigError(plot_option_check(""));
}

}  // namespace vdtnav::tools
