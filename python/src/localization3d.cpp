// 3D localization in Python: one cloud localized from a guess (localize3d, `vdtnav localize3d`
// on one scan) and the sequential 3D localizer with lost detection and recovery (Localizer3D).
#include <cmath>
#include <limits>
#include <mutex>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "numpy_points.hpp"
#include "results.hpp"
#include "vdtnav/estimation/global_localization3d.hpp"
#include "vdtnav/estimation/recovering_localizer3d.hpp"
#include "vdtnav/estimation/vdt_localizer3d.hpp"
#ifdef VDTNAV_PYTHON_3D_FILES
#include "vdtnav/pcl/cloud_observations.hpp"
#endif

namespace vdtnav::python {

#ifdef VDTNAV_PYTHON_3D_FILES
namespace {

/// The readings of a cloud (N x 3, sensor frame) as observations_from_cloud() makes them: the
/// path of `vdtnav localize3d` (PCL's float points, the same drops and voxel thinning).
ObservationSet3 observations(const py::array& cloud, double sigma_range, double range_min,
                             double range_max, double voxel, const py::object& sensor_in_robot) {
  const PointView<3> view(cloud, "cloud");
  pcl::PointCloud<pcl::PointXYZ> c;
  c.resize(view.size());
  constexpr std::size_t kBlock = 256;
  Eigen::Vector3d p[kBlock];
  for (std::size_t first = 0; first < view.size(); first += kBlock) {
    const std::size_t count = std::min(kBlock, view.size() - first);
    view.read(first, count, p);
    for (std::size_t k = 0; k < count; ++k)
      c[first + k] = pcl::PointXYZ(static_cast<float>(p[k].x()), static_cast<float>(p[k].y()),
                                   static_cast<float>(p[k].z()));
  }
  CloudObservationOptions o;
  o.sigma_range = sigma_range;
  o.range_min = range_min;
  o.range_max = range_max;
  o.voxel = voxel;
  if (!sensor_in_robot.is_none()) o.sensor_in_robot = to_pose3(sensor_in_robot, "sensor_in_robot");
  return observations_from_cloud(c, o);
}

VdtLocalizer3Options options3(const py::object& settings, int dof) {
  if (dof != 6 && dof != 4) throw ConfigError("dof: expected 6 or 4, got " + std::to_string(dof));
  VdtLocalizer3Options o = settings_from(settings, cloud_settings()).localize3d;
  o.optimizer.four_dof = dof == 4;
  return o;
}

struct Localizer3 {
  std::unique_ptr<std::mutex> mutex = std::make_unique<std::mutex>();  ///< one call at a time
  std::shared_ptr<Map3> map;
  std::unique_ptr<RecoveringLocalizer3> localizer;
  double sigma_range, range_min, range_max, voxel;
  py::object sensor_in_robot;
};

constexpr const char* kCloudArgs =
    " cloud: N x 3 (float32 or float64) in the sensor's frame; sigma_range: range noise, metres "
    "(default VLP-16's 0.03); voxel: thinning cube, metres (< 0: the map's resolution, as the "
    "CLI; 0: every reading); range_min / range_max: readings kept; sensor_in_robot: 4 x 4 pose "
    "of the sensor in the robot frame. NaN and inf points are dropped.";

}  // namespace
#endif

void bind_localization3d(py::module_& m) {
#ifdef VDTNAV_PYTHON_3D_FILES
  py::class_<OdometryStep3>(m, "OdometryStep3", "What odometry and an IMU report between scans.")
      .def(py::init([](const py::object& delta, double dt, double roll, double pitch) {
             OdometryStep3 o;
             o.delta = to_pose3(delta, "delta");
             o.dt = dt;
             o.roll = roll;
             o.pitch = pitch;
             return o;
           }),
           py::arg("delta"), py::arg("dt") = 0.0,
           py::arg("roll") = std::numeric_limits<double>::quiet_NaN(),
           py::arg("pitch") = std::numeric_limits<double>::quiet_NaN(),
           "The increment (4 x 4) in the previous robot frame over dt seconds, and the IMU's "
           "roll and pitch at this scan (radians; NaN: no IMU).")
      .def_readwrite("dt", &OdometryStep3::dt)
      .def_readwrite("roll", &OdometryStep3::roll)
      .def_readwrite("pitch", &OdometryStep3::pitch)
      .def_property(
          "delta", [](const OdometryStep3& o) { return pose_array(o.delta); },
          [](OdometryStep3& o, const py::object& d) { o.delta = to_pose3(d, "delta"); });

  m.def(
      "localize3d",
      [](std::shared_ptr<Map3> map, const py::array& cloud, const py::object& init, int dof,
         const py::object& settings, double sigma_range, double voxel, double range_min,
         double range_max, const py::object& sensor_in_robot) {
        const VdtLocalizer3Options o = options3(settings, dof);
        const Pose3 guess = to_pose3(init, "init");
        const ObservationSet3 obs =
            observations(cloud, sigma_range, range_min, range_max,
                         voxel < 0.0 ? map->field().resolution() : voxel, sensor_in_robot);
        py::gil_scoped_release release;
        const VdtOptimizationLocalizer3 localizer(map->field(), o);
        LocalizationResult3 r = localize_from_guess(localizer, obs, guess);
        if (dof == 4 && r.has_covariance)  // the held roll and pitch (vdt_localizer3d.hpp)
          r.covariance = localizer.with_held_attitude(obs, r, o.held_attitude_sigma);
        return r;
      },
      py::arg("map").none(false), py::arg("cloud"), py::arg("init"), py::arg("dof") = 6,
      py::arg("settings") = py::none(), py::arg("sigma_range") = 0.03, py::arg("voxel") = -1.0,
      py::arg("range_min") = 0.0, py::arg("range_max") = std::numeric_limits<double>::infinity(),
      py::arg("sensor_in_robot") = py::none(),
      (std::string("Localizes one cloud from the guess `init` (4 x 4), as `vdtnav localize3d` "
                   "does a single scan: Algorithm 1 in SE(3) (dof 6) or with roll and pitch held "
                   "(dof 4), refused when the solution explains less than accept_fraction. "
                   "settings: over Settings.cloud() (section localize3d). Returns a "
                   "LocalizationResult3 (4 x 4 pose, 6 x 6 covariance, status, explained).") +
       kCloudArgs)
          .c_str());

  py::class_<Localizer3>(m, "Localizer3D",
                         "The sequential 3D localizer with lost detection and recovery "
                         "(`vdtnav localize3d --scans`): make_localizer3d.")
      .def(
          "reset",
          [](Localizer3& self, const py::object& pose, const py::object& covariance) {
            const Pose3 p = to_pose3(pose, "pose");
            const Matrix6d c = to_matrix(covariance, 6, 6, "covariance");
            py::gil_scoped_release release;
            const std::lock_guard<std::mutex> lock(*self.mutex);
            self.localizer->reset(p, c);
          },
          py::arg("pose"), py::arg("covariance"))
      .def(
          "update",
          [](Localizer3& self, const py::object& odometry, const py::array& cloud) {
            OdometryStep3 o;
            if (py::isinstance<OdometryStep3>(odometry))
              o = odometry.cast<OdometryStep3>();
            else
              o.delta = to_pose3(odometry, "odometry");
            const ObservationSet3 obs =
                observations(cloud, self.sigma_range, self.range_min, self.range_max,
                             self.voxel < 0.0 ? self.map->field().resolution() : self.voxel,
                             self.sensor_in_robot);
            py::gil_scoped_release release;
            const std::lock_guard<std::mutex> lock(*self.mutex);  // one update at a time
            return self.localizer->update(o, obs);
          },
          py::arg("odometry"), py::arg("cloud"),
          "Predicts with the odometry (an OdometryStep3 or a 4 x 4 increment), corrects with the "
          "cloud. Returns a LocalizationResult3 (status lost while lost).")
      .def_property_readonly("name", [](const Localizer3& self) { return self.localizer->name(); })
      .def_property_readonly("recoveries",
                             [](const Localizer3& self) { return self.localizer->recoveries(); });

  py::class_<GlobalLocalization3Result>(m, "GlobalLocalization3",
                                        "What a 3D global localization found "
                                        "(global_localize3d).")
      .def_readonly("result", &GlobalLocalization3Result::result,
                    "The refined best pose (LocalizationResult3): status converged when "
                    "accepted, refused when unexplained or ambiguous.")
      .def_readonly("ambiguous", &GlobalLocalization3Result::ambiguous,
                    "A distinct pose explains the cloud as well: refused, not guessed.")
      .def_property_readonly(
          "alternatives",
          [](const GlobalLocalization3Result& g) {
            py::list l;
            for (const Pose3& p : g.alternatives) l.append(pose_array(p));
            return l;
          },
          "The distinct refined poses (4 x 4) that explain the cloud as well.")
      .def_readonly("explained", &GlobalLocalization3Result::explained,
                    "Fraction of the readings the best pose explains.")
      .def_readonly("nodes", &GlobalLocalization3Result::nodes, "Cubes scored.")
      .def_readonly("seconds", &GlobalLocalization3Result::seconds,
                    "Wall time of the search and the refinement.");

  m.def(
      "global_localize3d",
      [](std::shared_ptr<Map3> map, const py::array& cloud, double roll, double pitch,
         const py::object& settings, double sigma_range, double voxel, double range_min,
         double range_max, const py::object& sensor_in_robot) {
        VdtLocalizer3Options o = options3(settings, 6);
        GlobalLocalization3Options g = o.global;
        g.optimizer = o.optimizer;
        const ObservationSet3 obs =
            observations(cloud, sigma_range, range_min, range_max,
                         voxel < 0.0 ? map->field().resolution() : voxel, sensor_in_robot);
        py::gil_scoped_release release;
        const GlobalLocalizer3 global(map->field(), g);
        return global.localize(obs, roll, pitch);
      },
      py::arg("map").none(false), py::arg("cloud"), py::arg("roll") = 0.0, py::arg("pitch") = 0.0,
      py::arg("settings") = py::none(), py::arg("sigma_range") = 0.03, py::arg("voxel") = -1.0,
      py::arg("range_min") = 0.0, py::arg("range_max") = std::numeric_limits<double>::infinity(),
      py::arg("sensor_in_robot") = py::none(),
      (std::string("Localizes one cloud with no prior, as `vdtnav localize3d --init global` does "
                   "its first scans: branch and bound over x, y, z, yaw with roll and pitch "
                   "given (radians, from gravity; 0: level), refined in 6 DOF "
                   "(global_localization3d.hpp; settings: section localize3d.global). The search "
                   "grid is built on each call (~0.6 s on the CATEC map). Returns a "
                   "GlobalLocalization3.") +
       kCloudArgs)
          .c_str());

  m.def(
      "make_localizer3d",
      [](std::shared_ptr<Map3> map, int dof, const py::object& settings, double sigma_range,
         double voxel, double range_min, double range_max, const py::object& sensor_in_robot) {
        auto l = std::make_unique<Localizer3>();
        l->localizer =
            std::make_unique<RecoveringLocalizer3>(map->field(), options3(settings, dof));
        l->map = std::move(map);
        l->sigma_range = sigma_range;
        l->voxel = voxel;
        l->range_min = range_min;
        l->range_max = range_max;
        l->sensor_in_robot = sensor_in_robot;
        return l;
      },
      py::arg("map").none(false), py::arg("dof") = 6, py::arg("settings") = py::none(),
      py::arg("sigma_range") = 0.03, py::arg("voxel") = -1.0, py::arg("range_min") = 0.0,
      py::arg("range_max") = std::numeric_limits<double>::infinity(),
      py::arg("sensor_in_robot") = py::none(),
      (std::string("The sequential 3D localizer (vdt_localizer3d.hpp) with lost detection and "
                   "recovery, on `map`; reset() it at a pose first.") +
       kCloudArgs)
          .c_str());
#else
  (void)m;
#endif
}

}  // namespace vdtnav::python
