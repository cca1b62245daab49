#include "common.hpp"

#include <chrono>
#include <sstream>

#include "vdtnav/core/error.hpp"
#include "vdtnav/io/tum_trajectory.hpp"

namespace vdtnav::tools {

LoadedMap load_map(const std::string& yaml_path) {
  LoadedMap m;
  m.ros = load_ros_map(yaml_path);
  m.occupancy = occupancy(m.ros);
  const auto t0 = std::chrono::steady_clock::now();
  m.vdt = std::make_unique<VdtMap2>(VdtMap2::build(m.occupancy));
  m.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return m;
}

Pose2 parse_pose(const std::string& text, const std::string& what) {
  std::istringstream in(text);
  Pose2 p;
  char c1 = 0, c2 = 0;
  if (!(in >> p[0] >> c1 >> p[1] >> c2 >> p[2]) || c1 != ',' || c2 != ',' || !p.allFinite() ||
      !(in >> std::ws).eof()) {
    throw ConfigError(what + ": expected x,y,yaw (metres, metres, radians), got '" + text + "'");
  }
  p[2] = wrap_angle(p[2]);
  return p;
}

eval::Trajectory2 load_trajectory2(const std::string& tum_path) {
  const TumTrajectory tum = load_tum_trajectory(tum_path);
  eval::Trajectory2 out;
  out.reserve(tum.poses.size());
  for (const auto& s : tum.poses) out.push_back({s.t, pose2_from_pose3(s.pose)});
  return out;
}

void TimeWindow::add_options(CLI::App& app) {
  app.add_option("--from", from, "First time used, in the log's time base (seconds)");
  app.add_option("--to", to, "Last time used, in the log's time base (seconds)");
}

std::vector<std::size_t> scans_in(const CarmenLog& log, const TimeWindow& window) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < log.lasers.size(); ++i) {
    if (window.contains(log.lasers[i].time)) out.push_back(i);
  }
  return out;
}

}  // namespace vdtnav::tools
