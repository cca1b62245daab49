// load_odometry_table (raw odometry joined with corrected poses) on fuzzed text.
#include "fuzz_input.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/io/odometry_table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdtnav::fuzz::write(data, size, "table.txt");
  try {
    (void)vdtnav::load_odometry_table(path);
  } catch (const vdtnav::Error&) {
  }
  return 0;
}
