// load_ros_map on a fuzzed image (PGM, PNG, ... as stb_image decodes them) under a valid YAML.
#include "fuzz_input.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/io/ros_map.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string yaml = vdtnav::fuzz::write(
      std::string("image: map.img\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
                  "occupied_thresh: 0.65\nfree_thresh: 0.196\n"),
      "map.yaml");
  (void)vdtnav::fuzz::write(data, size, "map.img");
  try {
    const vdtnav::RosMap m = vdtnav::load_ros_map(yaml);
    (void)vdtnav::occupancy(m);
  } catch (const vdtnav::Error&) {
  }
  return 0;
}
