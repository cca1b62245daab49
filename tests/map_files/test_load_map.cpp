// load_map (vdtnav::map_files): each format gives the map its own reader gives, the dimension
// asked for is enforced, and the options a format does not take are refused as options.
#include "vdtnav/map_files/load_map.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "../io/test_files.hpp"
#include "../package/consumer/box_room_scan.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/io/vdt_map_file.hpp"
#include "vdtnav/mapping/uncertain_map_file.hpp"
#include "vdtnav/mapping/uncertain_vdt_map.hpp"

namespace vdtnav {
namespace {

/// A 2 m x 1.5 m room of 5 cm cells with a pillar; the outer ring unknown (-1) as a ROS map.
Grid<std::int8_t, 2> room_cells() {
  Grid<std::int8_t, 2> cells(Eigen::Vector2i(40, 30), GridFrame<2>(0.05, {-1.0, -0.5}, 0.0), 0);
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 30; ++j) {
      const bool ring = i == 0 || j == 0 || i == 39 || j == 29;
      const bool wall = i == 1 || j == 1 || i == 38 || j == 28 || (i >= 20 && i < 23 && j == 12);
      cells(Eigen::Vector2i(i, j)) = ring ? -1 : wall ? 100 : 0;
    }
  }
  return cells;
}

/// The maps agree at every node (values and nearest cells), as a map built from the same grid.
void expect_same_field(const VdtMap2& a, const VdtMap2& b) {
  ASSERT_EQ(a.nearest_cells().size(), b.nearest_cells().size());
  for (std::size_t i = 0; i < a.nearest_cells().num_cells(); ++i)
    ASSERT_EQ(a.nearest_cells()[i], b.nearest_cells()[i]) << i;
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(0.03, 0.21), Eigen::Vector2d(-0.6, 0.7)}) {
    const auto sa = a.evaluate(p), sb = b.evaluate(p);
    EXPECT_EQ(sa.value, sb.value);
  }
}

TEST(LoadMap, RosMapIsTheVdtOfItsOccupancyAndKeepsItsUnknownCells) {
  const std::string dir = test::tmp_dir("map_files");
  save_ros_map(dir + "/room", room_cells());
  const LoadedMap m = load_map(dir + "/room.yaml");
  EXPECT_EQ(m.dimension, 2);
  EXPECT_EQ(m.source, "ros map");
  EXPECT_EQ(m.ros.cells(Eigen::Vector2i(0, 0)), -1);  // unknown stays unknown
  const OccupancyGrid<2> occ = occupancy(room_cells());
  ASSERT_EQ(m.occupancy.values(), occ.values());
  expect_same_field(*m.vdt, VdtMap2::build(occ));
  EXPECT_GT(m.memory_bytes(), 0u);
}

TEST(LoadMap, Saved2dVdtMapGivesItsFeaturesAsTheOccupancy) {
  const std::string dir = test::tmp_dir("map_files");
  const OccupancyGrid<2> occ = occupancy(room_cells());
  const VdtMap2 built = VdtMap2::build(occ);
  save_vdt_map(dir + "/room.vdt", built);
  const LoadedMap m = load_map(dir + "/room.vdt", {}, 2);
  EXPECT_EQ(m.dimension, 2);
  EXPECT_EQ(m.source, "vdt map file");
  // Every occupied cell is its own nearest occupied cell, and only those are.
  ASSERT_EQ(m.occupancy.values(), occ.values());
  expect_same_field(*m.vdt, built);
}

TEST(LoadMap, Saved3dVdtMapIsDense3dAndTheDimensionAskedForIsEnforced) {
  const std::string dir = test::tmp_dir("map_files");
  OccupancyGrid<3> occ(Eigen::Vector3i(8, 8, 8), GridFrame<3>(0.1, Eigen::Vector3d::Zero()), 0);
  occ(Eigen::Vector3i(4, 4, 4)) = 1;
  save_vdt_map(dir + "/cube.vdt", VdtMap3::build(occ));
  const LoadedMap m = load_map(dir + "/cube.vdt");
  EXPECT_EQ(m.dimension, 3);
  ASSERT_TRUE(m.dense != nullptr);
  EXPECT_EQ(m.sparse, nullptr);
  EXPECT_DOUBLE_EQ(m.field3().resolution(), 0.1);
  EXPECT_THROW((void)load_map(dir + "/cube.vdt", {}, 2), ConfigError);
  save_ros_map(dir + "/room", room_cells());
  EXPECT_THROW((void)load_map(dir + "/room.yaml", {}, 3), ConfigError);
}

TEST(LoadMap, OptionsASavedMapDoesNotTakeAreRefusedAsOptions) {
  const std::string dir = test::tmp_dir("map_files");
  OccupancyGrid<3> occ(Eigen::Vector3i(8, 8, 8), GridFrame<3>(0.1, Eigen::Vector3d::Zero()), 0);
  occ(Eigen::Vector3i(4, 4, 4)) = 1;
  save_vdt_map(dir + "/cube.vdt", VdtMap3::build(occ));
  MapLoadOptions crop;
  crop.crop = parse_crop_box("0,0,0,1,1,1", "--crop");
  EXPECT_THROW((void)load_map(dir + "/cube.vdt", crop), MapOptionError);
  MapLoadOptions other;
  other.resolution = 0.2;  // the saved map has 0.1
  EXPECT_THROW((void)load_map(dir + "/cube.vdt", other), MapOptionError);
  MapLoadOptions bad;
  bad.margin = -1.0;
  EXPECT_THROW((void)load_map(dir + "/cube.vdt", bad), MapOptionError);
  EXPECT_THROW((void)parse_crop_box("0,0,0,1,1", "--crop"), MapOptionError);
  EXPECT_THROW((void)parse_crop_box("0,0,0,1,-1,1", "--crop"), MapOptionError);
}

TEST(LoadMap, UncertainMapFileIsReadByItsMagicWhateverItsName) {
  const std::string dir = test::tmp_dir("map_files");
  mapping::MapScan ms;
  ms.pose = Pose2(2.0, 1.5, 0.0);
  ms.pose_covariance = Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal();
  ms.points = scan_points(box_room_scan());
  const auto um = mapping::UncertainVdtMap::fit({ms}, mapping::UncertainMapOptions{});
  const OccupancyGrid<2> room = box_room();
  Grid<std::int8_t, 2> cells(room.size(), room.frame(), 0);
  for (std::size_t i = 0; i < room.num_cells(); ++i) cells[i] = room[i] != 0 ? 100 : 0;
  mapping::save_uncertain_map(dir + "/room.yaml", um, cells);  // named like a ROS map
  const LoadedMap m = load_map(dir + "/room.yaml", {}, 2);
  EXPECT_EQ(m.source, "uncertain map file");
  ASSERT_TRUE(m.uncertain != nullptr);
  ASSERT_EQ(m.occupancy.values(), room.values());
  // The VDT map samples the fitted field: a point 12.5 cm below the wall y = 2.725 m.
  const auto s = m.vdt->evaluate(Eigen::Vector2d(2.0, 2.6));
  const auto f = um.evaluate(Eigen::Vector2d(2.0, 2.6));
  ASSERT_TRUE(s.inside && f.inside);
  EXPECT_NEAR(s.value.y(), f.value.y(), 0.01);
  EXPECT_NEAR(s.value.y(), -0.125, 0.01);
}

TEST(LoadMap, AMissingFileIsAnIoErrorNamingIt) {
  try {
    (void)load_map("/nonexistent/room.yaml");
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/room.yaml"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vdtnav
