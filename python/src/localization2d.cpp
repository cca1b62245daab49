// 2D localization in Python: settings (dicts or YAML files over the CLI's defaults), laser scans
// and odometry steps, every method of make_localizer() with lost detection and recovery, global
// localization, and the results of both 2D and 3D localizers.
#include <mutex>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.hpp"
#include "numpy_points.hpp"
#include "results.hpp"
#include "vdtnav/estimation/global_localization.hpp"
#include "vdtnav/estimation/localizer_config.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/io/log_odometry.hpp"

namespace vdtnav::python {

LocalizerSettings settings_from(const py::object& settings, const LocalizerSettings& defaults) {
  if (settings.is_none()) return defaults;
  if (py::isinstance<LocalizerSettings>(settings)) return settings.cast<LocalizerSettings>();
  if (py::isinstance<py::dict>(settings)) {
    // JSON is YAML: the dict goes through the settings file's reader, so its keys, types and
    // error messages are the file's ("<dict>:1: vdt-opt.loss: ...").
    const std::string text = py::str(py::module_::import("json").attr("dumps")(settings));
    return parse_localizer_config(text, "<dict>", defaults);
  }
  if (py::isinstance<py::str>(settings) || py::hasattr(settings, "__fspath__"))
    return load_localizer_config(py::str(settings), defaults);
  throw py::type_error("settings: expected None, a vdtnav.Settings, a dict or a path");
}

void check_scan(const LaserScan& scan, const char* what) {
  if (!scan.angles.empty() && scan.angles.size() != scan.ranges.size())
    throw py::value_error(std::string(what) + ": " + std::to_string(scan.ranges.size()) +
                          " ranges but " + std::to_string(scan.angles.size()) +
                          " angles (one angle per range, or none: angle_min + i angle_increment)");
}

std::string status_token(LocalizationStatus s) {
  std::string t = to_string(s);
  for (char& c : t)
    if (c == ' ') c = '_';
  return t;
}

namespace {

template <int Dim>
void bind_result(py::module_& m, const char* name, const char* doc) {
  using R = LocalizationResultT<Dim>;
  py::class_<R>(m, name, doc)
      .def_property_readonly(
          "pose", [](const R& r) { return pose_array(r.pose); },
          Dim == 2 ? "(x, y, phi): metres, radians" : "4 x 4 homogeneous pose")
      .def_property_readonly(
          "covariance", [](const R& r) { return to_array(Eigen::MatrixXd(r.covariance)); },
          Dim == 2 ? "3 x 3 covariance of (x, y, phi)"
                   : "6 x 6 covariance of the left perturbation (dt, dtheta) "
                     "in the world frame; NaN rows for held components")
      .def_property_readonly(
          "status", [](const R& r) { return status_token(r.status); },
          "converged, not_converged, too_few_observations, diverged, refused, "
          "lost or bridged")
      .def_property_readonly("converged",
                             [](const R& r) { return r.status == LocalizationStatus::kConverged; })
      .def_property_readonly(
          "published", [](const R& r) { return published_by_default(r.status); },
          "whether the CLI's default TUM file and the ROS node hold this pose "
          "(converged or bridged)")
      .def_readonly("has_covariance", &R::has_covariance)
      .def_readonly("iterations", &R::iterations, "solver iterations of the whole update")
      .def_readonly("explained", &R::explained,
                    "fraction of the observations the map explains at the pose (< 0: not measured)")
      .def_readonly("inliers", &R::inliers)
      .def_readonly("dropped", &R::dropped)
      .def_readonly("final_cost", &R::final_cost)
      .def_property_readonly(
          "work",
          [](const R& r) {
            py::dict d;
            d["solves"] = r.work.solves;
            d["coarse_to_fine"] = r.work.coarse_to_fine;
            d["window_searches"] = r.work.window_searches;
            d["bridged"] = r.work.bridged;
            d["global_searches"] = r.work.global_searches;
            d["search_boxes"] = r.work.search_boxes;
            d["candidates"] = r.work.candidates;
            return d;
          },
          "what the update ran besides one solve: solves, coarse_to_fine, window_searches, "
          "bridged, global_searches, search_boxes, candidates (localizer.hpp's Work)")
      .def("__repr__", [name](const R& r) {
        return std::string("<vdtnav.") + name + " " + status_token(r.status) + ", " +
               std::to_string(r.iterations) + " iterations>";
      });
}

OdometryStep odometry_from(const py::object& odometry, double dt) {
  if (py::isinstance<OdometryStep>(odometry)) return odometry.cast<OdometryStep>();
  // An increment in the previous robot frame: the step odometry_steps() makes of it.
  const Pose2 delta = to_pose2(odometry, "odometry");
  return odometry_steps({0.0, dt}, {Pose2::Zero(), delta})[1];
}

LaserScan scan_from(const py::object& scan, const py::object& ranges, const py::object& angles,
                    const py::object& angle_min, const py::object& angle_increment,
                    double range_min, double range_max, double sigma_range) {
  if (!scan.is_none()) {
    if (!ranges.is_none()) throw py::value_error("update: give scan or ranges, not both");
    LaserScan s = scan.cast<LaserScan>();
    check_scan(s, "scan");
    return s;
  }
  if (ranges.is_none()) throw py::value_error("update: give a scan or ranges");
  LaserScan s;
  s.ranges = to_doubles(ranges, "ranges");
  if (!angles.is_none()) {
    s.angles = to_doubles(angles, "angles");
    check_scan(s, "angles");
  } else {
    if (angle_min.is_none() || angle_increment.is_none())
      throw py::value_error("update: give angles, or angle_min and angle_increment");
    s.angle_min = angle_min.cast<double>();
    s.angle_increment = angle_increment.cast<double>();
  }
  s.range_min = range_min;
  s.range_max = range_max;
  s.sigma_range = sigma_range;
  return s;
}

}  // namespace

void bind_results(py::module_& m) {
  bind_result<2>(m, "LocalizationResult", "The result of a 2D localization step.");
  bind_result<3>(m, "LocalizationResult3", "The result of a 3D localization step.");
}

void bind_localization2d(py::module_& m) {
  py::class_<LocalizerSettings>(
      m, "Settings",
      "Every localizer setting (docs/settings.md; `vdtnav localize --print-config`). Read from "
      "YAML or a dict with the settings file's sections and keys: unknown keys, wrong types and "
      "non-finite numbers raise ConfigError naming the key.")
      .def(py::init<>(),
           "The defaults (`vdtnav localize`'s, the C++ constructors', the ROS node's): real logs "
           "on maps drawn from scans.")
      .def_static("log", &log_settings, "The defaults, by name: the same as Settings().")
      .def_static("exact_map", &exact_map_settings,
                  "The thesis's localizers on an exact map (generated floor plans): no robust "
                  "loss, 25 iterations, no map-error correlation, the velocity motion model.")
      .def_static("cloud", &cloud_settings, "`vdtnav localize3d`'s defaults: real 3D clouds.")
      .def_static(
          "load",
          [](const std::filesystem::path& path, const py::object& base) {
            return load_localizer_config(path.string(), settings_from(base, log_settings()));
          },
          py::arg("path"), py::arg("base") = py::none(),
          "A YAML settings file read over `base` (default Settings.log()).")
      .def_static(
          "from_yaml",
          [](const std::string& text, const py::object& base) {
            return parse_localizer_config(text, "<yaml>", settings_from(base, log_settings()));
          },
          py::arg("text"), py::arg("base") = py::none())
      .def(
          "updated",
          [](const LocalizerSettings& self, const py::dict& keys) {
            return settings_from(keys, self);
          },
          py::arg("keys"),
          "These settings with the keys of a dict ({'vdt-opt': {'loss': 'huber'}}).")
      .def("yaml", &localizer_settings_yaml, py::arg("method") = "",
           "The settings as a documented YAML file (all sections, or one method's).");

  bind_results(m);

  py::class_<LaserScan>(m, "LaserScan", "One planar scan (sensor_msgs/LaserScan semantics).")
      .def(py::init([](const py::object& ranges, const py::object& angles, double angle_min,
                       double angle_increment, double range_min, double range_max,
                       double sigma_range, const py::object& mount, double time) {
             LaserScan s;
             s.ranges = to_doubles(ranges, "ranges");
             if (!angles.is_none()) s.angles = to_doubles(angles, "angles");
             s.angle_min = angle_min;
             s.angle_increment = angle_increment;
             s.range_min = range_min;
             s.range_max = range_max;
             s.sigma_range = sigma_range;
             if (!mount.is_none()) s.mount = to_pose2(mount, "mount");
             s.time = time;
             check_scan(s, "LaserScan");
             return s;
           }),
           py::arg("ranges"), py::arg("angles") = py::none(), py::arg("angle_min") = 0.0,
           py::arg("angle_increment") = 0.0, py::arg("range_min") = 0.1,
           py::arg("range_max") = 30.0, py::arg("sigma_range") = 0.02,
           py::arg("mount") = py::none(), py::arg("time") = 0.0,
           "ranges (metres; NaN, inf and readings outside [range_min, range_max) are dropped), "
           "explicit angles or angle_min + i angle_increment (radians), the range noise "
           "sigma_range (metres), the sensor's mount (x, y, phi) in the robot frame.")
      .def_property(
          "ranges",
          [](const LaserScan& s) {
            return to_array(Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(
                s.ranges.data(), static_cast<Eigen::Index>(s.ranges.size()))));
          },
          [](LaserScan& s, const py::object& r) { s.ranges = to_doubles(r, "ranges"); })
      .def_property(
          "angles",
          [](const LaserScan& s) {
            check_scan(s, "angles");
            Eigen::VectorXd a(static_cast<Eigen::Index>(s.ranges.size()));
            for (std::size_t i = 0; i < s.ranges.size(); ++i)
              a[static_cast<Eigen::Index>(i)] = s.angle(i);
            return to_array(a);
          },
          [](LaserScan& s, const py::object& a) { s.angles = to_doubles(a, "angles"); },
          "every beam's angle (explicit or from angle_min and angle_increment)")
      .def_readwrite("time", &LaserScan::time)
      .def_readwrite("angle_min", &LaserScan::angle_min)
      .def_readwrite("angle_increment", &LaserScan::angle_increment)
      .def_readwrite("range_min", &LaserScan::range_min)
      .def_readwrite("range_max", &LaserScan::range_max)
      .def_readwrite("sigma_range", &LaserScan::sigma_range)
      .def_property(
          "mount", [](const LaserScan& s) { return pose_array(s.mount); },
          [](LaserScan& s, const py::object& p) { s.mount = to_pose2(p, "mount"); })
      .def(
          "points",
          [](const LaserScan& s) {
            check_scan(s, "points");
            const ScanPoints p = scan_points(s);
            Eigen::MatrixXd a(static_cast<Eigen::Index>(p.size()), 2);
            for (std::size_t i = 0; i < p.size(); ++i)
              a.row(static_cast<Eigen::Index>(i)) = p.points[i].transpose();
            return to_array(a);
          },
          "The valid beams' endpoints in the robot frame (N x 2), as the localizers use them.");

  py::class_<OdometryStep>(m, "OdometryStep", "What odometry reports between two scans.")
      .def(py::init([](const py::object& delta, double dt) {
             return odometry_steps({0.0, dt}, {Pose2::Zero(), to_pose2(delta, "delta")})[1];
           }),
           py::arg("delta"), py::arg("dt") = 0.0,
           "The increment (dx, dy, dphi) in the previous robot frame over dt seconds; v and w "
           "are its arc length and turn over dt (as odometry_steps makes them).")
      .def_readwrite("dt", &OdometryStep::dt)
      .def_readwrite("v", &OdometryStep::v)
      .def_readwrite("w", &OdometryStep::w)
      .def_property(
          "delta", [](const OdometryStep& o) { return pose_array(o.delta); },
          [](OdometryStep& o, const py::object& d) { o.delta = to_pose2(d, "delta"); });

  m.def(
      "odometry_steps",
      [](const py::object& times, const py::object& poses) {
        const std::vector<double> t = to_doubles(times, "times");
        const Eigen::MatrixXd p = to_matrix(poses, static_cast<py::ssize_t>(t.size()), 3, "poses");
        std::vector<Pose2> ps;
        for (Eigen::Index k = 0; k < p.rows(); ++k) ps.push_back(p.row(k).transpose());
        return odometry_steps(t, ps);
      },
      py::arg("times"), py::arg("poses"),
      "The steps between consecutive odometry poses (N x 3) at `times`: step k from pose k-1 to "
      "pose k (step 0 zero).");

  m.def("localizer_methods", &localizer_methods, "The methods make_localizer knows.");

  py::class_<Localizer2>(m, "Localizer2D",
                         "A 2D localizer (make_localizer): predict with odometry, correct with a "
                         "scan, one step at a time.")
      .def(
          "reset",
          [](Localizer2& self, const py::object& pose, const py::object& covariance) {
            const Pose2 p = to_pose2(pose, "pose");
            const Eigen::Matrix3d c = to_matrix(covariance, 3, 3, "covariance");
            py::gil_scoped_release release;
            const std::lock_guard<std::mutex> lock(*self.mutex);
            self.localizer->reset(p, c);
          },
          py::arg("pose"), py::arg("covariance"), "Starts (again) at pose with covariance.")
      .def(
          "update",
          [](Localizer2& self, const py::object& odometry, const py::object& scan,
             const py::object& ranges, const py::object& angles, const py::object& angle_min,
             const py::object& angle_increment, double range_min, double range_max,
             double sigma_range, double dt) {
            const OdometryStep o = odometry_from(odometry, dt);
            const LaserScan s = scan_from(scan, ranges, angles, angle_min, angle_increment,
                                          range_min, range_max, sigma_range);
            py::gil_scoped_release release;
            const std::lock_guard<std::mutex> lock(*self.mutex);  // one update at a time
            return self.localizer->update(o, s);
          },
          py::arg("odometry"), py::arg("scan") = py::none(), py::kw_only(),
          py::arg("ranges") = py::none(), py::arg("angles") = py::none(),
          py::arg("angle_min") = py::none(), py::arg("angle_increment") = py::none(),
          py::arg("range_min") = 0.1, py::arg("range_max") = 30.0, py::arg("sigma_range") = 0.02,
          py::arg("dt") = 0.0,
          "Predicts with the odometry (an OdometryStep, or an increment (dx, dy, dphi) over dt "
          "seconds), then corrects with a LaserScan or ranges with angles (or angle_min and "
          "angle_increment). Returns a LocalizationResult; the GIL is released meanwhile.")
      .def_property_readonly("name", [](const Localizer2& self) { return self.localizer->name(); })
      .def_property_readonly(
          "recoveries",
          [](const Localizer2& self) -> py::object {
            const auto* r = dynamic_cast<const RecoveringLocalizer*>(self.localizer.get());
            if (r == nullptr) return py::none();
            return py::int_(r->recoveries());
          },
          "Re-acquisitions after being lost (None: no lost detection around this method).")
      .def_property_readonly("map", [](const Localizer2& self) { return self.map; });

  m.def(
      "make_localizer",
      [](const std::string& method, std::shared_ptr<Map2> map, const py::object& settings,
         bool knowledge) {
        auto l = std::make_unique<Localizer2>();
        l->settings = settings_from(settings, log_settings());
        l->localizer = make_localizer(method, *map->vdt, map->occupancy, l->settings,
                                      knowledge ? map->knowledge : MapKnowledge());
        l->map = std::move(map);
        return l;
      },
      py::arg("method"), py::arg("map").none(false), py::arg("settings") = py::none(),
      py::arg("knowledge") = true,
      "A 2D localizer by name (localizer_methods()): vdt-opt, thesis Algorithm 1 (minimises "
      "d_VCD = sum_i |d_i|^2, eq. 2.17, over the gated beams, 3.3; covariance by the implicit "
      "function theorem, 3.4-3.6 as corrected in SPEC); vdt-ekf, the EKF on the VDT (prediction "
      "3.7-3.10, innovation -d_i, 3.12, S = H P H^T + R, 3.13); the baselines udt-opt, udt-ekf "
      "(Chamfer on the unsigned distance) and pf (AMCL-style); active-ekf and passive-ekf (one "
      "rotating beam, thesis Ch. 4). settings: a Settings, a dict or a YAML file over "
      "Settings.log() "
      "(`vdtnav localize`'s defaults; None: those). vdt-opt and vdt-ekf come with lost detection "
      "and recovery unless settings['recovery']['detect'] is false. knowledge: hold scans into "
      "the map's unknown cells not against it. Raises ConfigError for an unknown method.");

  py::class_<GlobalLocalizationResult>(m, "GlobalLocalizationResult")
      .def_readonly("result", &GlobalLocalizationResult::result,
                    "the refined pose: converged when accepted, refused when the scan is "
                    "unexplained or the pose ambiguous")
      .def_readonly("ambiguous", &GlobalLocalizationResult::ambiguous)
      .def_property_readonly(
          "alternatives",
          [](const GlobalLocalizationResult& r) {
            Eigen::MatrixXd a(static_cast<Eigen::Index>(r.alternatives.size()), 3);
            for (std::size_t i = 0; i < r.alternatives.size(); ++i)
              a.row(static_cast<Eigen::Index>(i)) = r.alternatives[i].transpose();
            return to_array(a);
          })
      .def_readonly("explained", &GlobalLocalizationResult::explained)
      .def_readonly("nodes", &GlobalLocalizationResult::nodes)
      .def_readonly("seconds", &GlobalLocalizationResult::seconds);

  m.def(
      "global_localize",
      [](std::shared_ptr<Map2> map, const LaserScan& scan, const py::object& settings) {
        check_scan(scan, "scan");
        const LocalizerSettings s = settings_from(settings, log_settings());
        GlobalLocalizationOptions g = s.global;
        g.optimizer = s.vdt_opt;  // the refinement: vdt-opt's solve, as `vdtnav localize`
        const ScanPoints points = scan_points(scan);
        py::gil_scoped_release release;
        const GlobalLocalizer global(*map->vdt, map->occupancy, g, map->knowledge);
        return global.localize(points);
      },
      py::arg("map").none(false), py::arg("scan"), py::arg("settings") = py::none(),
      "Global localization from no prior (branch and bound on the VDT's min-pooled pyramid, "
      "then vdt-opt's refinement; `vdtnav localize --init global`): refused when the scan is "
      "unexplained or ambiguous (alternatives).");
}

}  // namespace vdtnav::python
