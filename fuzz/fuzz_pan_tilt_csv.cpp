// parse_pan_tilt_csv (the pan-tilt point laser's readings) on fuzzed text.
#include <sstream>
#include <string>

#include "vdtnav/core/error.hpp"
#include "vdtnav/point_laser/pan_tilt_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  for (const bool skip : {false, true}) {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    vdtnav::point_laser::PanTiltCsvOptions o;
    o.skip_malformed = skip;
    try {
      (void)vdtnav::point_laser::parse_pan_tilt_csv(in, "fuzz.csv", o);
    } catch (const vdtnav::Error&) {
    }
  }
  return 0;
}
