// A user's program against the installed vdtnav::ros: a LaserScan message as a scan, a transform
// interpolated by the buffer, and a path that is no bag refused with vdtnav's error.
#include <vdtnav/core/error.hpp>
#include <vdtnav/ros/bag_reader.hpp>
#include <vdtnav/ros/scan_sequence.hpp>
#include <vdtnav/ros/transform_buffer.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>

int main(int argc, char** argv) {
  using namespace vdtnav;
  if (argc != 2) return 2;
  ros::LaserScanMsg m;
  m.angle_increment = 0.5F;
  m.range_min = 0.1F;
  m.range_max = 10.0F;
  m.ranges = {1.0F, std::nanf(""), 2.0F};
  const ScanPoints p = scan_points(ros::to_laser_scan(m, Pose2::Zero(), 0.02, std::nan("")));
  ros::TransformBuffer tf(10.0);
  ros::TransformStampedMsg t;
  t.header.frame_id = "odom";
  t.child_frame_id = "base_link";
  t.translation.x() = 0.0;
  tf.add(t, false);
  t.header.stamp_ns = 1000000000;
  t.translation.x() = 1.0;
  tf.add(t, false);
  const double x = tf.lookup("odom", "base_link", 500000000).translation().x();
  std::ofstream(argv[1]) << "not a bag\n";
  bool refused = false;
  try {
    (void)ros::BagReader::open(argv[1]);
  } catch (const FormatError&) {
    refused = true;
  }
  std::printf("consumer_ros: %zu points, x(0.5 s) = %.3f, refused: %d\n", p.size(), x,
              refused ? 1 : 0);
  return p.size() == 2 && std::abs(x - 0.5) < 1e-9 && refused ? 0 : 1;
}
