// The C++ side of the bindings' tests (python/tests): the same computations through the C++ API
// directly, printed with 17 significant digits, so that pytest compares the Python results with
// them (equal to 1e-12; in practice bit for bit).
//
//   cpp_reference lookup MAP.yaml POINTS.txt         one line per point: value, jacobian, inside
//   cpp_reference localize MAP.yaml LOG METHOD N     one line per scan: pose, covariance, status,
//                                                    iterations, solves, window searches
//   cpp_reference localize3d MAP CLOUD DOF X Y Z ROLL PITCH YAW   pose (4 x 4), covariance, status
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/map_files/load_map.hpp"
#include "vdtnav/pcl/cloud_observations.hpp"
#include "vdtnav/pcl/point_cloud_file.hpp"

using namespace vdtnav;

namespace {

void print_matrix(const Eigen::MatrixXd& m) {
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) std::printf(" %.17g", m(i, j));
}

int lookup(const std::string& map_path, const std::string& points_path) {
  const RosMap ros = load_ros_map(map_path);
  const VdtMap2 vdt = VdtMap2::build(occupancy(ros));
  std::ifstream in(points_path);
  std::vector<Eigen::Vector2d> p;
  double x, y;
  while (in >> x >> y) p.emplace_back(x, y);
  std::vector<VdtSample<2>> s(p.size());
  vdt.evaluate(p.data(), p.size(), s.data(), true);
  for (const VdtSample<2>& q : s) {
    print_matrix(q.value);
    print_matrix(q.jacobian);
    std::printf(" %d\n", q.inside ? 1 : 0);
  }
  return 0;
}

int localize(const std::string& map_path, const std::string& log_path, const std::string& method,
             std::size_t n) {
  const RosMap ros = load_ros_map(map_path);
  const OccupancyGrid<2> occ = occupancy(ros);
  const VdtMap2 vdt = VdtMap2::build(occ);
  const CarmenLog log = load_carmen_log(log_path);
  std::vector<std::size_t> idx;
  std::vector<double> times;
  for (std::size_t i = 0; i < n && i < log.lasers.size(); ++i) {
    idx.push_back(i);
    times.push_back(log.lasers[i].time);
  }
  const std::vector<OdometryStep> steps = odometry_steps(times, log_odometry(log, idx).poses);
  const auto loc = make_localizer(method, vdt, occ, log_settings(), MapKnowledge(ros.cells));
  loc->reset(log.lasers[0].pose, Eigen::Vector3d(0.01, 0.01, 0.0025).asDiagonal());
  for (std::size_t k = 0; k < idx.size(); ++k) {
    LaserScan scan = log.lasers[k].scan;
    scan.sigma_range = 0.02;
    const LocalizationResult r = loc->update(steps[k], scan);
    print_matrix(r.pose);
    print_matrix(r.covariance);
    std::printf(" %d %d %d %d\n", static_cast<int>(r.status), r.iterations, r.work.solves,
                r.work.window_searches);
  }
  return 0;
}

int localize3d(char** argv) {
  const LoadedMap map = load_map(argv[2], MapLoadOptions{}, 3);
  const int dof = std::stoi(argv[4]);
  VdtLocalizer3Options o = cloud_settings().localize3d;
  o.optimizer.four_dof = dof == 4;
  const Pose3 guess =
      pose3_from_xyz_rpy(std::stod(argv[5]), std::stod(argv[6]), std::stod(argv[7]),
                         std::stod(argv[8]), std::stod(argv[9]), std::stod(argv[10]));
  CloudObservationOptions co;
  co.voxel = map.field3().resolution();
  const ObservationSet3 obs = observations_from_cloud(read_point_cloud(argv[3]), co);
  const VdtOptimizationLocalizer3 localizer(map.field3(), o);
  LocalizationResult3 r = localize_from_guess(localizer, obs, guess);
  if (dof == 4 && r.has_covariance)
    r.covariance = localizer.with_held_attitude(obs, r, o.held_attitude_sigma);
  print_matrix(r.pose.matrix());
  print_matrix(r.covariance);
  std::printf(" %d %.17g\n", static_cast<int>(r.status), r.explained);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string what = argc > 1 ? argv[1] : "";
    if (what == "lookup" && argc == 4) return lookup(argv[2], argv[3]);
    if (what == "localize" && argc == 6)
      return localize(argv[2], argv[3], argv[4], std::stoul(argv[5]));
    if (what == "localize3d" && argc == 11) return localize3d(argv);
  } catch (const vdtnav::Error& e) {
    std::fprintf(stderr, "cpp_reference: %s\n", e.what());
    return 1;
  }
  std::fprintf(stderr, "usage: see the file comment of python/tests/cpp_reference.cpp\n");
  return 2;
}
