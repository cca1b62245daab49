// A user's program against the installed vdtnav::point_laser: pan-tilt readings from CSV text,
// columns in any order, a no-return reading kept as such.
#include <vdtnav/point_laser/pan_tilt_csv.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>

int main() {
  using namespace vdtnav::point_laser;
  std::istringstream csv("range,pan,tilt\n2.5,0.1,-0.2\ninf,0.3,0.0  # no return\n");
  const PanTiltCsv r = parse_pan_tilt_csv(csv, "readings.csv");
  const bool ok = r.readings.size() == 2 && r.readings[0].range == 2.5 &&
                  r.readings[0].pan == 0.1 && r.readings[0].tilt == -0.2 &&
                  std::isinf(r.readings[1].range) && !r.has_time;
  std::printf("%zu readings: %s\n", r.readings.size(), ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
