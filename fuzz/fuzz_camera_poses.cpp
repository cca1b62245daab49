// read_camera_poses (the RGB-D frames' pose file) on fuzzed text.
#include "fuzz_input.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/rgbd_ground/rgbd_frame.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdtnav::fuzz::write(data, size, "pose.txt");
  try {
    (void)vdtnav::rgbd_ground::read_camera_poses(path);
  } catch (const vdtnav::Error&) {
  }
  return 0;
}
