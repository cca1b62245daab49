// A user's program against the installed vdtnav::io: save and reload a built map.
#include <vdtnav/io/vdt_map_file.hpp>

#include <cstdio>

int main(int argc, char** argv) {
  using namespace vdtnav;
  if (argc < 2) return 2;
  OccupancyGrid<2> occ(Eigen::Vector2i(16, 12), GridFrame<2>(0.05, Eigen::Vector2d(1, 2)), 0);
  occ(Eigen::Vector2i(3, 4)) = 1;
  const auto map = VdtMap2::build(occ);
  save_vdt_map(argv[1], map);
  const auto back = load_vdt_map<2>(argv[1]);
  const Eigen::Vector2d p(1.3, 2.2);
  const bool ok = (back.evaluate(p).value - map.evaluate(p).value).norm() == 0.0;
  std::printf("round trip: %s\n", ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
