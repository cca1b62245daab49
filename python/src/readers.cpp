// Readers in Python: CARMEN logs (and the raw-odometry table join), relations, TUM trajectories
// and point clouds, as numpy arrays; errors raise with the readers' messages (file:line: what).
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.hpp"
#include "numpy_points.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/io/odometry_table.hpp"
#include "vdtnav/io/relations.hpp"
#include "vdtnav/io/tum_trajectory.hpp"
#ifdef VDTNAV_PYTHON_3D_FILES
#include "vdtnav/pcl/point_cloud_file.hpp"
#endif

namespace vdtnav::python {
namespace {

template <typename F>
py::array_t<double> rows(std::size_t n, py::ssize_t cols, F&& row) {
  py::array_t<double> a({static_cast<py::ssize_t>(n), cols});
  double* d = a.mutable_data();
  for (std::size_t i = 0; i < n; ++i) row(i, d + static_cast<py::ssize_t>(i) * cols);
  return a;
}

py::array_t<double> pose_rows(const std::vector<Pose2>& poses) {
  return rows(poses.size(), 3, [&](std::size_t i, double* r) {
    for (int k = 0; k < 3; ++k) r[k] = poses[i][k];
  });
}

}  // namespace

void bind_readers(py::module_& m) {
  py::class_<CarmenLog, std::shared_ptr<CarmenLog>>(
      m, "CarmenLog", "A CARMEN log's laser messages (FLASER, ROBOTLASER1) and ODOM lines.")
      .def("__len__", [](const CarmenLog& l) { return l.lasers.size(); })
      .def_property_readonly(
          "times",
          [](const CarmenLog& l) {
            Eigen::VectorXd t(static_cast<Eigen::Index>(l.lasers.size()));
            for (std::size_t i = 0; i < l.lasers.size(); ++i)
              t[static_cast<Eigen::Index>(i)] = l.lasers[i].time;
            return to_array(t);
          },
          "each scan's time, seconds")
      .def_property_readonly(
          "poses",
          [](const CarmenLog& l) {
            return rows(l.lasers.size(), 3, [&](std::size_t i, double* r) {
              for (int k = 0; k < 3; ++k) r[k] = l.lasers[i].pose[k];
            });
          },
          "each scan's laser pose (x, y, theta): corrected poses in corrected logs, odometry in "
          "raw")
      .def_property_readonly(
          "odom",
          [](const CarmenLog& l) {
            return rows(l.lasers.size(), 3, [&](std::size_t i, double* r) {
              for (int k = 0; k < 3; ++k) r[k] = l.lasers[i].odom[k];
            });
          },
          "each scan's odometry pose (x, y, theta)")
      .def(
          "scan",
          [](const CarmenLog& l, py::ssize_t i) {
            const auto n = static_cast<py::ssize_t>(l.lasers.size());
            if (i < -n || i >= n)
              throw py::index_error("scan " + std::to_string(i) + " of " + std::to_string(n));
            return l.lasers[static_cast<std::size_t>(i < 0 ? i + n : i)].scan;
          },
          py::arg("i"), "Scan i as a LaserScan (a copy; negative i counts from the end).")
      .def_property_readonly("scans",
                             [](const CarmenLog& l) {
                               std::vector<LaserScan> s;
                               s.reserve(l.lasers.size());
                               for (const auto& x : l.lasers) s.push_back(x.scan);
                               return s;
                             })
      .def_property_readonly(
          "ranges",
          [](const CarmenLog& l) -> py::object {
            if (l.lasers.empty()) return py::none();
            const std::size_t b = l.lasers[0].scan.ranges.size();
            for (const auto& x : l.lasers)
              if (x.scan.ranges.size() != b) return py::none();
            return rows(
                l.lasers.size(), static_cast<py::ssize_t>(b), [&](std::size_t i, double* r) {
                  std::copy(l.lasers[i].scan.ranges.begin(), l.lasers[i].scan.ranges.end(), r);
                });
          },
          "the ranges, scans x beams (None when scans differ in beam count)")
      .def_property_readonly(
          "lines",
          [](const CarmenLog& l) {
            std::vector<std::size_t> v;
            for (const auto& x : l.lasers) v.push_back(x.line);
            return v;
          },
          "each scan's 1-based line in the file")
      .def_readonly("params", &CarmenLog::params);

  m.def(
      "read_carmen_log",
      [](const std::filesystem::path& path, double max_range, double range_min,
         bool skip_malformed) {
        CarmenLogOptions o;
        o.max_range = max_range;
        o.range_min = range_min;
        o.skip_malformed = skip_malformed;
        py::gil_scoped_release release;
        return std::make_shared<CarmenLog>(load_carmen_log(path.string(), o));
      },
      py::arg("path"), py::arg("max_range") = 80.0, py::arg("range_min") = 0.1,
      py::arg("skip_malformed") = false,
      "Reads a CARMEN log (plain or gzip). max_range: the no-return threshold (metres); raises "
      "FormatError `file:line: what was expected` for a malformed line.");

  m.def(
      "join_odometry_table",
      [](const CarmenLog& log, const std::filesystem::path& table_path) {
        JoinedLogs j =
            join_odometry_table(log, load_odometry_table(table_path.string()), table_path.string());
        return py::make_tuple(std::make_shared<CarmenLog>(std::move(j.raw)),
                              std::make_shared<CarmenLog>(std::move(j.corrected)));
      },
      py::arg("log"), py::arg("table_path"),
      "Joins a corrected log with a raw-odometry table (`vdtnav join-odometry`): (raw, corrected) "
      "logs on the table's absolute time base.");

  m.def(
      "log_odometry",
      [](const CarmenLog& log, const std::vector<std::size_t>& scans) {
        for (std::size_t i : scans)
          if (i >= log.lasers.size()) throw py::index_error("scan " + std::to_string(i));
        return pose_rows(log_odometry(log, scans).poses);
      },
      py::arg("log"), py::arg("scans"),
      "The odometry pose at each scan of `scans` (ODOM lines interpolated, else the scans' odom "
      "fields), N x 3.");

  m.def(
      "read_relations",
      [](const std::filesystem::path& path) {
        const RelationsFile f = load_relations(path.string());
        return rows(f.relations.size(), 5, [&](std::size_t i, double* r) {
          const Relation& x = f.relations[i];
          r[0] = x.t1;
          r[1] = x.t2;
          for (int k = 0; k < 3; ++k) r[2 + k] = x.delta[k];
        });
      },
      py::arg("path"),
      "Reads a relation file (Kümmerle et al. 2009): N x 5 rows (t1, t2, x, y, yaw), the pose at "
      "t2 in the frame of the pose at t1.");

  m.def(
      "read_tum",
      [](const std::filesystem::path& path) {
        const TumTrajectory t = load_tum_trajectory(path.string());
        return rows(t.poses.size(), 8, [&](std::size_t i, double* r) {
          const StampedPose3& s = t.poses[i];
          const Eigen::Quaterniond q(s.pose.linear());
          r[0] = s.t;
          for (int k = 0; k < 3; ++k) r[1 + k] = s.pose.translation()[k];
          r[4] = q.x();
          r[5] = q.y();
          r[6] = q.z();
          r[7] = q.w();
        });
      },
      py::arg("path"), "Reads a TUM trajectory: N x 8 rows (t, x, y, z, qx, qy, qz, qw).");

  m.def(
      "write_tum",
      [](const std::filesystem::path& path, const py::object& times, const py::object& poses) {
        const std::vector<double> t = to_doubles(times, "times");
        const auto a =
            py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(poses);
        const auto n = static_cast<py::ssize_t>(t.size());
        std::vector<StampedPose3> s;
        if (a && a.ndim() == 3 && a.shape(0) == n && a.shape(1) == 4 && a.shape(2) == 4) {
          for (py::ssize_t i = 0; i < n; ++i) {
            Pose3 p = Pose3::Identity();
            p.matrix() = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(a.data(i));
            s.push_back({t[static_cast<std::size_t>(i)], p});
          }
        } else {
          const Eigen::MatrixXd p = to_matrix(poses, n, 3, "poses (N x 3 or N x 4 x 4)");
          for (py::ssize_t i = 0; i < n; ++i)
            s.push_back({t[static_cast<std::size_t>(i)], pose3_from_pose2(p.row(i).transpose())});
        }
        save_tum_trajectory(path.string(), s);
      },
      py::arg("path"), py::arg("times"), py::arg("poses"),
      "Writes a TUM trajectory: planar poses (N x 3) or 4 x 4 poses (N x 4 x 4); `vdtnav eval "
      "--traj` reads it.");

#ifdef VDTNAV_PYTHON_3D_FILES
  m.def(
      "read_point_cloud",
      [](const std::filesystem::path& path) {
        const pcl::PointCloud<pcl::PointXYZ> c = read_point_cloud(path.string());
        return rows(c.size(), 3, [&](std::size_t i, double* r) {
          r[0] = c[i].x;
          r[1] = c[i].y;
          r[2] = c[i].z;
        });
      },
      py::arg("path"),
      "Reads a point cloud (.pcd, .ply, .vtk, text/CSV with x, y, z columns) as N x 3 float64 "
      "(NaN points kept: the localizers drop them).");
#endif
}

}  // namespace vdtnav::python
