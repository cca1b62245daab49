// load_ros_map on a fuzzed YAML, a valid 3 x 2 PGM beside it (fuzz_ros_map_image fuzzes images).
#include "fuzz_input.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/io/ros_map.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string image = vdtnav::fuzz::write(
      std::string("P5\n3 2\n255\n") + std::string("\x00\xff\x80\x10\xfe\x01", 6), "good.pgm");
  const std::string yaml = vdtnav::fuzz::write(data, size, "map.yaml");
  try {
    const vdtnav::RosMap m = vdtnav::load_ros_map(yaml);
    (void)vdtnav::occupancy(m);
  } catch (const vdtnav::Error&) {
  }
  return 0;
}
