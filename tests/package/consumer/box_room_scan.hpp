#pragma once
// The scan the consumers share: 360 exact beams from (2.0, 1.5, 0) in a 4 m x 3 m box room whose
// walls run through the cell centres x = 0.275, 3.725 and y = 0.275, 2.725 (5 cm cells).
#include <vdtnav/map/grid.hpp>
#include <vdtnav/sensor/laser_scan.hpp>

#include <algorithm>
#include <cmath>

inline vdtnav::OccupancyGrid<2> box_room() {
  using namespace vdtnav;
  OccupancyGrid<2> occ(Eigen::Vector2i(80, 60), GridFrame<2>(0.05, Eigen::Vector2d::Zero()), 0);
  for (int i = 0; i < 80; ++i) occ(Eigen::Vector2i(i, 5)) = occ(Eigen::Vector2i(i, 54)) = 1;
  for (int j = 0; j < 60; ++j) occ(Eigen::Vector2i(5, j)) = occ(Eigen::Vector2i(74, j)) = 1;
  return occ;
}

inline vdtnav::LaserScan box_room_scan() {
  vdtnav::LaserScan scan;
  scan.angle_min = -M_PI;
  scan.angle_increment = 2 * M_PI / 360;
  for (int k = 0; k < 360; ++k) {
    const double a = scan.angle(k), c = std::cos(a), s = std::sin(a);
    const double tx = c > 0 ? (3.725 - 2.0) / c : c < 0 ? (0.275 - 2.0) / c : 1e9;
    const double ty = s > 0 ? (2.725 - 1.5) / s : s < 0 ? (0.275 - 1.5) / s : 1e9;
    scan.ranges.push_back(std::min(tx, ty));
  }
  return scan;
}
