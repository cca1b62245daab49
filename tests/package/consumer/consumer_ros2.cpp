// A user's program against the installed vdtnav::ros2: ROS 2's names on DDS and a launch file's
// command line, without a network (no participant is created).
#include <vdtnav/ros2/dds.hpp>
#include <vdtnav/ros2/ros_args.hpp>

#include <cstdio>
#include <string>

int main() {
  using namespace vdtnav::ros2;
  const char* argv[] = {"node", "--ros-args", "-r", "__node:=amcl", "-r", "scan:=/front/scan"};
  const RosArgs args(6, argv, "vdtnav_ros2_localizer");
  const bool ok = dds_topic_name("/amcl_pose") == "rt/amcl_pose" &&
                  dds_type_name("geometry_msgs/msg/PoseWithCovarianceStamped") ==
                      "geometry_msgs::msg::dds_::PoseWithCovarianceStamped_" &&
                  args.node_name() == "amcl" && args.resolve("scan") == "/front/scan";
  std::printf("consumer_ros2: %s, %s\n", args.fully_qualified_name().c_str(),
              ok ? "names as ROS 2 maps them" : "WRONG");
  return ok ? 0 : 1;
}
