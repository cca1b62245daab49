// read_point_cloud's own parsers (text x y z with or without a header, legacy ASCII VTK) on fuzzed
// bytes; the first byte picks the format. PCD and PLY are PCL's readers and not fuzzed here.
#include "fuzz_input.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/pcl/point_cloud_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const kNames[] = {"cloud.csv", "cloud.xyz", "cloud.vtk"};
  const std::string path = vdtnav::fuzz::write(data + 1, size - 1, kNames[data[0] % 3]);
  try {
    (void)vdtnav::read_point_cloud(path);
  } catch (const vdtnav::Error&) {
  }
  return 0;
}
