// load_carmen_log on fuzzed text, strict and skipping malformed lines.
#include "fuzz_input.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/io/carmen_log.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdtnav::fuzz::write(data, size, "run.log");
  for (const bool skip : {false, true}) {
    vdtnav::CarmenLogOptions o;
    o.skip_malformed = skip;
    try {
      const vdtnav::CarmenLog log = vdtnav::load_carmen_log(path, o);
      for (const auto& l : log.lasers) (void)vdtnav::scan_points(l.scan);
    } catch (const vdtnav::Error&) {
    }
  }
  return 0;
}
