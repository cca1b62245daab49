// read_point_set_csv, 2D and 3D, on fuzzed text.
#include "fuzz_input.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/io/point_set_map.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdtnav::fuzz::write(data, size, "points.csv");
  try {
    (void)vdtnav::read_point_set_csv<2>(path);
  } catch (const vdtnav::Error&) {
  }
  try {
    (void)vdtnav::read_point_set_csv<3>(path);
  } catch (const vdtnav::Error&) {
  }
  return 0;
}
