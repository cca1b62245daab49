// load_tum_trajectory on fuzzed text, strict and skipping malformed lines.
#include "fuzz_input.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/io/tum_trajectory.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdtnav::fuzz::write(data, size, "traj.tum");
  for (const bool skip : {false, true}) {
    vdtnav::TumOptions o;
    o.skip_malformed = skip;
    try {
      (void)vdtnav::load_tum_trajectory(path, o);
    } catch (const vdtnav::Error&) {
    }
  }
  return 0;
}
