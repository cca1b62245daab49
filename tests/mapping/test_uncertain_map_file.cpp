// The uncertain map file (.umap): a fitted map saved and mapped back answers every query as the
// fitted one (values, Jacobians, covariances, the joint propagate()), keeps its occupancy
// rendering, and a damaged file is refused with what is wrong.
#include "vdtnav/mapping/uncertain_map_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/sim/mapping_run.hpp"

namespace vdtnav::mapping {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Fitted {
  sim::MappingRun run;
  UncertainVdtMap map;
};

const Fitted& fitted() {
  static const Fitted f = [] {
    const sim::MappingScene scene = sim::l_shaped_room(0.01);
    sim::LidarOptions l;
    l.fov = kPi;
    l.angular_resolution = 0.5 * kPi / 180.0;
    l.range_max = 10.0;
    sim::MappingRun run =
        sim::simulate_mapping_run(scene.world, scene.poses, l, sim::MappingNoise::table_5_1(), 11);
    UncertainMapOptions o;
    o.spacing = 0.2;
    UncertainVdtMap map = UncertainVdtMap::fit(run.scans, o);
    return Fitted{std::move(run), std::move(map)};
  }();
  return f;
}

Grid<std::int8_t, 2> rendering() {
  Grid<std::int8_t, 2> g(Eigen::Vector2i(7, 5), GridFrame<2>(0.05, Eigen::Vector2d(-1.0, 2.0), 0.3),
                         -1);
  g(Eigen::Vector2i(3, 2)) = 100;
  g(Eigen::Vector2i(0, 0)) = 0;
  return g;
}

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          (name + "_" + std::to_string(::getpid()) + ".umap"))
      .string();
}

std::vector<unsigned char> read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void write_all(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

TEST(UncertainMapFile, RoundTripAnswersEveryQueryAsTheFittedMap) {
  const Fitted& f = fitted();
  ASSERT_TRUE(f.map.summary().covariance_ok);
  const std::string path = temp_path("round_trip");
  save_uncertain_map(path, f.map, rendering());
  EXPECT_TRUE(is_uncertain_map_file(path));
  const UncertainMapFile loaded = load_uncertain_map(path);
  std::filesystem::remove(path);  // mapped: the pages stay readable until the map goes
  EXPECT_EQ(loaded.map.band_cells(), f.map.band_cells());
  EXPECT_EQ(loaded.map.spacing(), f.map.spacing());
  EXPECT_EQ(loaded.map.approximation_sigma(), f.map.approximation_sigma());
  EXPECT_EQ(loaded.map.observed_points().size(), f.map.observed_points().size());
  // The occupancy rendering, cell for cell, and its frame.
  const Grid<std::int8_t, 2> g = rendering();
  ASSERT_EQ(loaded.occupancy.size(), g.size());
  EXPECT_EQ(loaded.occupancy.frame().origin(), g.frame().origin());
  EXPECT_EQ(loaded.occupancy.frame().yaw(), g.frame().yaw());
  for (std::size_t k = 0; k < g.num_cells(); ++k) EXPECT_EQ(loaded.occupancy[k], g[k]);
  // Every query, bit for bit (the same arrays, read where they lie in the file).
  int inside = 0;
  std::vector<Eigen::Vector2d> q;
  std::vector<MapUncertainty2::Sensitivity> s;
  for (std::size_t k = 0; k < f.run.true_boundary.size(); k += 11) {
    const Eigen::Vector2d p = f.run.true_boundary[k] + Eigen::Vector2d(0.03, -0.02);
    const UncertainMapSample a = f.map.evaluate(p), b = loaded.map.evaluate(p);
    ASSERT_EQ(a.inside, b.inside);
    if (!a.inside) continue;
    ++inside;
    EXPECT_EQ(a.value, b.value);
    EXPECT_EQ(a.jacobian, b.jacobian);
    EXPECT_EQ(a.covariance, b.covariance);
    q.push_back(p);
    s.push_back(MapUncertainty2::Sensitivity::Constant(0.3 + 0.01 * static_cast<double>(k % 7)));
  }
  EXPECT_GT(inside, 50);
  EXPECT_EQ(f.map.propagate(q, s, nullptr), loaded.map.propagate(q, s, nullptr));
  // The sampled field the localizers read.
  const VdtMap2 va = f.map.to_vdt_map(0.05), vb = loaded.map.to_vdt_map(0.05);
  ASSERT_EQ(va.size(), vb.size());
  for (const Eigen::Vector2d& p : q) EXPECT_EQ(va.evaluate(p).value, vb.evaluate(p).value);
}

TEST(UncertainMapFile, RefusesADamagedFileWithWhatIsWrong) {
  const Fitted& f = fitted();
  const std::string path = temp_path("damaged");
  save_uncertain_map(path, f.map, rendering());
  const std::vector<unsigned char> good = read_all(path);
  const auto refused = [&](const std::vector<unsigned char>& bytes, const std::string& what) {
    write_all(path, bytes);
    try {
      (void)load_uncertain_map(path);
      ADD_FAILURE() << "accepted a file with " << what;
    } catch (const FormatError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  std::vector<unsigned char> b = good;
  b[0] = 'X';
  refused(b, "not an uncertain map file");
  b = good;
  b[8] = 2;  // version
  refused(b, "unsupported format version 2");
  b = good;
  b[20] ^= 0x10;  // the spacing
  refused(b, "header checksum mismatch");
  b = good;
  b[good.size() / 2] ^= 0x40;  // a byte of the body
  refused(b, "checksum mismatch");
  b.assign(good.begin(), good.end() - 8);
  refused(b, "truncated file");
  b = good;
  b.push_back(0);
  refused(b, "unexpected data after the map");
  // Without the payload's checksum the damaged byte goes unnoticed, but every size is checked.
  b = good;
  b[good.size() - 4] ^= 0x01;
  write_all(path, b);
  EXPECT_NO_THROW((void)load_uncertain_map(path, false));
  EXPECT_THROW((void)load_uncertain_map(path, true), FormatError);
  std::filesystem::remove(path);
  EXPECT_THROW((void)load_uncertain_map(path), IoError);
  EXPECT_FALSE(is_uncertain_map_file(path));
}

}  // namespace
}  // namespace vdtnav::mapping
