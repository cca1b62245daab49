// read_calibration (the UAV camera's calibration: camera_info YAML or OpenCV YAML/XML) on
// fuzzed text.
#include "fuzz_input.hpp"
#include "vdtnav/camera/camera_model.hpp"
#include "vdtnav/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdtnav::fuzz::write(data, size, "camera.yaml");
  try {
    (void)vdtnav::camera::read_calibration(path);
  } catch (const vdtnav::Error&) {
  }
  return 0;
}
