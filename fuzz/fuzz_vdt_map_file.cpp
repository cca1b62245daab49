// load_vdt_map (the binary VDT map file), 2D and 3D, on fuzzed bytes.
#include "fuzz_input.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/io/vdt_map_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdtnav::fuzz::write(data, size, "map.vdt");
  try {
    (void)vdtnav::load_vdt_map<2>(path);
  } catch (const vdtnav::Error&) {
  }
  try {
    (void)vdtnav::load_vdt_map<3>(path);
  } catch (const vdtnav::Error&) {
  }
  return 0;
}
