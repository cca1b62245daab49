// Bags in Python (built with the ROS front end, vdtnav::ros): the topics of a ROS 1 or ROS 2 bag,
// a 2D LiDAR run (`vdtnav localize --bag`'s input: scans with odometry and mounting) and the
// point clouds of a 3D run, as numpy arrays.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.hpp"
#include "numpy_points.hpp"
#ifdef VDTNAV_PYTHON_ROS
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/cloud_sequence.hpp"
#include "vdtnav/ros/scan_sequence.hpp"
#endif

namespace vdtnav::python {

void bind_bags(py::module_& m) {
#ifdef VDTNAV_PYTHON_ROS
  m.def(
      "bag_topics",
      [](const std::filesystem::path& path) {
        const std::unique_ptr<ros::BagReader> bag = ros::BagReader::open(path.string());
        py::list out;
        for (const ros::BagTopic& t : bag->topics()) {
          py::dict d;
          d["name"] = t.name;
          d["type"] = t.type;
          d["count"] = t.count;
          d["first"] = static_cast<double>(t.first_ns) * 1e-9;
          d["last"] = static_cast<double>(t.last_ns) * 1e-9;
          out.append(d);
        }
        return out;
      },
      py::arg("path"),
      "The topics of a ROS 1 bag (.bag) or ROS 2 bag (folder): name, type, count, first and last "
      "recorded times (s), as `vdtnav bag info` lists them.");

  m.def(
      "read_bag_scans",
      [](const std::filesystem::path& path, const std::string& scan_topic,
         const std::string& odom_topic, const std::string& odom_frame,
         const std::string& base_frame, const py::object& laser_pose, double sigma_range,
         double max_range) {
        ros::ScanSequenceOptions o;
        o.scan_topic = scan_topic;
        o.odom_topic = odom_topic;
        o.odom_frame = odom_frame;
        o.base_frame = base_frame;
        if (!laser_pose.is_none()) o.laser_pose = to_pose2(laser_pose, "laser_pose");
        o.sigma_range = sigma_range;
        o.max_range = max_range;
        ros::ScanSequence s;
        {
          const std::unique_ptr<ros::BagReader> bag = ros::BagReader::open(path.string());
          py::gil_scoped_release release;
          s = ros::read_scan_sequence(*bag, o);
        }
        Eigen::VectorXd t(static_cast<Eigen::Index>(s.scans.size()));
        Eigen::MatrixXd odo(static_cast<Eigen::Index>(s.scans.size()), 3);
        for (std::size_t i = 0; i < s.scans.size(); ++i) {
          t[static_cast<Eigen::Index>(i)] = s.scans[i].time;
          odo.row(static_cast<Eigen::Index>(i)) = s.odometry[i].transpose();
        }
        py::dict d;
        d["scans"] = s.scans;
        d["times"] = to_array(t);
        d["odometry"] = to_array(odo);
        d["scan_topic"] = s.scan_topic;
        d["odometry_source"] = s.odometry_source;
        d["mount_source"] = s.mount_source;
        d["skipped_no_odometry"] = s.skipped_no_odometry;
        d["skipped_no_transform"] = s.skipped_no_transform;
        d["scan_topic_choice"] = s.scan_topic_choice;
        return d;
      },
      py::arg("path"), py::arg("scan_topic") = "", py::arg("odom_topic") = "",
      py::arg("odom_frame") = "odom", py::arg("base_frame") = "base_link",
      py::arg("laser_pose") = py::none(), py::arg("sigma_range") = 0.02,
      py::arg("max_range") = std::numeric_limits<double>::quiet_NaN(),
      "A 2D LiDAR run from a bag (`vdtnav localize --bag`): a dict with scans (LaserScans, mount "
      "set from TF or laser_pose), times (s), odometry (N x 3, base_frame in odom_frame at each "
      "scan, from odom_topic, TF or the only Odometry topic) and where each came from. "
      "odometry_steps(times, odometry) gives the localizers' steps.");

  m.def(
      "read_bag_clouds",
      [](const std::filesystem::path& path, const std::string& cloud_topic,
         const std::string& odom_topic, const std::string& imu_topic, const std::string& odom_frame,
         const std::string& base_frame, const py::object& lidar_pose, std::size_t max_clouds) {
        ros::CloudSequenceOptions o;
        o.cloud_topic = cloud_topic;
        o.odom_topic = odom_topic;
        o.imu_topic = imu_topic;
        o.odom_frame = odom_frame;
        o.base_frame = base_frame;
        if (!lidar_pose.is_none()) o.lidar_pose = to_pose3(lidar_pose, "lidar_pose");
        const std::unique_ptr<ros::BagReader> bag = ros::BagReader::open(path.string());
        py::list out;
        ros::read_cloud_sequence(*bag, o, [&](const ros::CloudFrame& f) {
          py::dict d;
          d["stamp"] = static_cast<double>(f.stamp_ns) * 1e-9;
          d["frame"] = f.frame;
          Eigen::MatrixXd p(static_cast<Eigen::Index>(f.cloud.points.size()), 3);
          for (std::size_t i = 0; i < f.cloud.points.size(); ++i)
            p.row(static_cast<Eigen::Index>(i)) = f.cloud.points[i].transpose();
          d["points"] = to_array(p);
          d["times"] =
              f.cloud.times.empty()
                  ? py::object(py::none())
                  : py::object(to_array(Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(
                        f.cloud.times.data(), static_cast<Eigen::Index>(f.cloud.times.size())))));
          d["mount"] = pose_array(f.mount);
          d["odometry"] = f.odometry ? py::object(pose_array(*f.odometry)) : py::object(py::none());
          d["roll"] = f.roll;
          d["pitch"] = f.pitch;
          out.append(d);
          return max_clouds == 0 || out.size() < max_clouds;
        });
        return out;
      },
      py::arg("path"), py::arg("cloud_topic") = "", py::arg("odom_topic") = "",
      py::arg("imu_topic") = "", py::arg("odom_frame") = "odom",
      py::arg("base_frame") = "base_link", py::arg("lidar_pose") = py::none(),
      py::arg("max_clouds") = 0,
      "The PointCloud2 messages of a bag (`vdtnav localize3d --bag`): a list of dicts with stamp "
      "(s), frame, points (N x 3, the cloud's frame, NaN points dropped), times (per point, s "
      "after the stamp, or None), mount (4 x 4, cloud frame in base_frame), odometry (4 x 4 or "
      "None) and the IMU's roll and pitch (NaN: none). max_clouds: stop after so many (0: all).");
#else
  (void)m;
#endif
}

}  // namespace vdtnav::python
