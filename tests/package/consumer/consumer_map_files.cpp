// A user's program against the installed vdtnav::map_files: a map_server map saved and loaded
// back by load_map, the loader every front end shares.
#include <vdtnav/io/ros_map.hpp>
#include <vdtnav/map_files/load_map.hpp>

#include <cmath>
#include <cstdio>

#include "box_room_scan.hpp"

int main() {
  using namespace vdtnav;
  const OccupancyGrid<2> occ = box_room();
  Grid<std::int8_t, 2> cells(occ.size(), occ.frame(), 0);
  for (std::size_t i = 0; i < occ.num_cells(); ++i) cells[i] = occ[i] != 0 ? 100 : 0;
  save_ros_map("consumer_room", cells);
  const LoadedMap m = load_map("consumer_room.yaml", MapLoadOptions{}, 2);
  const auto wall = m.vdt->evaluate(Eigen::Vector2d(2.0, 2.6));  // 12.5 cm below y = 2.725
  const bool ok = m.dimension == 2 && wall.inside && std::abs(wall.value.y() + 0.125) < 0.01;
  std::printf("load_map: %s, DT_y %g below a wall: %s\n", m.source.c_str(), wall.value.y(),
              ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
