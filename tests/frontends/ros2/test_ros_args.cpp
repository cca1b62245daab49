// The command line a ROS 2 launch file gives a node (ros_args.hpp), against the rules of ROS 2's
// design article "ROS command line arguments" and what nav2's launch files pass to amcl.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/ros2/ros_args.hpp"

namespace {

namespace fs = std::filesystem;
using vdtnav::ros2::RosArgs;

RosArgs parse(const std::vector<std::string>& args) {
  std::vector<const char*> argv = {"vdtnav_ros2_localizer"};
  for (const std::string& a : args) argv.push_back(a.c_str());
  return RosArgs(static_cast<int>(argv.size()), argv.data(), "vdtnav_ros2_localizer");
}

fs::path write(const std::string& name, const std::string& text) {
  const fs::path p = fs::path(VDTNAV_TEST_TMP) / name;
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  return p;
}

TEST(RosArgs, NodeNameNamespaceAndRemappingsResolveAsRclResolvesThem) {
  const RosArgs a = parse({"--own-flag", "--ros-args", "-r", "__node:=amcl", "-r", "__ns:=/robot1",
                           "-r", "scan:=/front/scan", "--remap", "amcl:map:=/shared_map", "-r",
                           "other_node:initialpose:=/nowhere", "--", "tail"});
  EXPECT_EQ(a.node_name(), "amcl");
  EXPECT_EQ(a.node_namespace(), "/robot1");
  EXPECT_EQ(a.fully_qualified_name(), "/robot1/amcl");
  EXPECT_EQ(a.resolve("scan"), "/front/scan");          // relative: in the namespace, remapped
  EXPECT_EQ(a.resolve("/robot1/scan"), "/front/scan");  // the same name written absolute
  EXPECT_EQ(a.resolve("map"), "/shared_map");           // a rule for this node
  EXPECT_EQ(a.resolve("initialpose"), "/robot1/initialpose");  // another node's rule
  EXPECT_EQ(a.resolve("/tf"), "/tf");
  EXPECT_EQ(a.resolve("~/status"), "/robot1/amcl/status");
  EXPECT_EQ(a.program_args(),
            (std::vector<std::string>{"vdtnav_ros2_localizer", "--own-flag", "tail"}));
}

TEST(RosArgs, AParamsFileGivesTheNodesBlockOverTheWildcardAndDashPOverrides) {
  const fs::path f = write("ros_args/nav2_params.yaml", R"(/**:
  ros__parameters:
    use_sim_time: True
    base_frame_id: wildcard_base
amcl:
  ros__parameters:
    base_frame_id: "base_footprint"
    update_min_d: 0.25
    tf_broadcast: false
    initial_pose:
      x: 1.5
      yaw: -0.5
map_server:
  ros__parameters:
    yaml_filename: "elsewhere.yaml"
)");
  const RosArgs a =
      parse({"--ros-args", "-r", "__node:=amcl", "--params-file", f.string(), "-p",
             "update_min_d:=0.5", "--log-level", "info", "-p", "scan_topic:=front_scan"});
  EXPECT_EQ(a.text("base_frame_id", ""), "base_footprint");
  EXPECT_TRUE(a.boolean("use_sim_time", false));
  EXPECT_DOUBLE_EQ(a.number("update_min_d", 0.0), 0.5);  // -p after the file
  EXPECT_FALSE(a.boolean("tf_broadcast", true));
  EXPECT_DOUBLE_EQ(a.number("initial_pose.x", 0.0), 1.5);
  EXPECT_DOUBLE_EQ(a.number("initial_pose.yaw", 0.0), -0.5);
  EXPECT_DOUBLE_EQ(a.number("initial_pose.y", 7.0), 7.0);  // not given: the default
  EXPECT_FALSE(a.has("yaml_filename"));                    // another node's
  EXPECT_EQ(a.text("scan_topic", "scan"), "front_scan");
  // A value of the wrong type names the parameter and where it came from.
  try {
    (void)a.number("base_frame_id", 0.0);
    FAIL() << "a string read as a number";
  } catch (const vdtnav::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("base_frame_id"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(f.string()), std::string::npos) << e.what();
  }
}

TEST(RosArgs, MalformedArgumentsAndFilesAreRefusedWithWhere) {
  EXPECT_THROW(parse({"--ros-args", "-p", "no_value"}), vdtnav::ConfigError);
  EXPECT_THROW(parse({"--ros-args", "-r"}), vdtnav::ConfigError);
  EXPECT_THROW(parse({"--ros-args", "--bogus"}), vdtnav::ConfigError);
  EXPECT_THROW(parse({"--ros-args", "--params-file", "/nonexistent/params.yaml"}), vdtnav::IoError);
  const fs::path bad = write("ros_args/bad.yaml", "vdtnav_ros2_localizer:\n  not_params: 1\n");
  try {
    (void)parse({"--ros-args", "--params-file", bad.string()});
    FAIL() << "a block without ros__parameters";
  } catch (const vdtnav::FormatError& e) {
    EXPECT_EQ(e.line(), 1U);
    EXPECT_NE(std::string(e.what()).find("ros__parameters"), std::string::npos) << e.what();
  }
  const fs::path broken = write("ros_args/broken.yaml", "amcl:\n  ros__parameters: [\n");
  EXPECT_THROW(parse({"--ros-args", "--params-file", broken.string()}), vdtnav::FormatError);
}

}  // namespace
