#include "vdtnav/io/relations.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.hpp"

namespace vdtnav {
namespace {

using test::lines_of;
using test::tmp_dir;
using test::write_file;

namespace fs = std::filesystem;

const std::string kIntelRelations = std::string(VDTNAV_DATA_DIR) + "/intel-lab/intel.relations";
const std::string kKillianRelations =
    std::string(VDTNAV_DATA_DIR) + "/mit-killian/mit-killian.relations";

std::string message_of(const std::string& path) {
  try {
    (void)load_relations(path);
  } catch (const FormatError& e) {
    return e.what();
  }
  return "no error";
}

void expect_same(const Relation& a, const Relation& b) {
  EXPECT_EQ(a.t1, b.t1);
  EXPECT_EQ(a.t2, b.t2);
  EXPECT_EQ(a.delta, b.delta);
}

TEST(RelationsIntel, EveryLineMatchesAnIndependentParse) {
  if (!fs::exists(kIntelRelations)) GTEST_SKIP() << "real data not found at " << kIntelRelations;
  const RelationsFile file = load_relations(kIntelRelations);
  const std::vector<std::string> lines = lines_of(kIntelRelations);
  ASSERT_EQ(lines.size(), 2984U);
  ASSERT_EQ(file.relations.size(), 2984U);
  EXPECT_TRUE(file.malformed_lines.empty());
  double lo = 1e300, hi = -1e300;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    std::istringstream s(lines[k]);
    double v[8];
    for (double& x : v) s >> x;  // strtod, like any C++ stream
    ASSERT_TRUE(static_cast<bool>(s)) << lines[k];
    const Relation& r = file.relations[k];
    EXPECT_EQ(r.t1, v[0]);
    EXPECT_EQ(r.t2, v[1]);
    EXPECT_EQ(r.delta, Pose2(v[2], v[3], v[7]));
    lo = std::min({lo, r.t1, r.t2});
    hi = std::max({hi, r.t1, r.t2});
  }
  // README: absolute intel.clf time base, 976052896 .. 976055541.
  EXPECT_GE(lo, 976052896.0);
  EXPECT_LT(lo, 976052897.0);
  EXPECT_GE(hi, 976055541.0);
  EXPECT_LT(hi, 976055542.0);
  // The first line, read by eye.
  expect_same(file.relations[0],
              Relation{976052905.167303, 976052911.885496, Pose2(-0.056990, -0.128430, -1.682210)});
}

TEST(RelationsKillian, LoadsEveryLine) {
  if (!fs::exists(kKillianRelations)) {
    GTEST_SKIP() << "real data not found at " << kKillianRelations;
  }
  const RelationsFile file = load_relations(kKillianRelations);
  EXPECT_EQ(file.relations.size(), 4677U);  // wc -l
  EXPECT_EQ(file.relations[0].t1, 1031745836.957);
  EXPECT_EQ(file.relations[0].delta, Pose2(0.444640, 0.000510, -0.000800));
}

TEST(Relations, MalformedLinesNameFileAndLine) {
  const std::string dir = tmp_dir("relations");
  struct Case {
    const char* name;
    const char* line;
    const char* what;
  };
  const Case cases[] = {
      {"bad_z", "1 2 0.1 0.2 0.5 0 0 0.3",
       "z: expected 0 (a planar relation: z, roll and pitch 0 within 1e-9), got '0.5'"},
      {"bad_roll", "1 2 0.1 0.2 0 2e-9 0 0.3", "roll: expected 0 (a planar relation"},
      {"bad_pitch", "1 2 0.1 0.2 0 0 -0.01 0.3", "pitch: expected 0"},
      {"few", "1 2 0.1 0.2 0 0 0", "expected 8 fields (t1 t2 x y z roll pitch yaw), found 7"},
      {"many", "1 2 0.1 0.2 0 0 0 0.3 9",
       "expected 8 fields (t1 t2 x y z roll pitch yaw), "
       "found more than 8"},
      {"word", "1 2 0.1 y 0 0 0 0.3", "y: expected a finite number, got 'y'"},
      {"nan", "1 nan 0.1 0.2 0 0 0 0.3", "t2: expected a finite number, got 'nan'"},
  };
  const std::string good = "976052905.167303 976052911.885496 -0.05699 -0.12843 0 0 0 -1.68221\n";
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/" + c.name + ".relations";
    write_file(path, "# t1 t2 x y z roll pitch yaw\n" + good + "\n" + good + c.line + "\n" + good);
    const std::string msg = message_of(path);
    EXPECT_EQ(msg.rfind(path + ":5: " + c.what, 0), 0U) << msg;
    RelationsOptions o;
    o.skip_malformed = true;
    const RelationsFile file = load_relations(path, o);
    EXPECT_EQ(file.malformed_lines, std::vector<std::size_t>{5});
    EXPECT_EQ(file.relations.size(), 3U);
  }
  // Within 1e-9 of zero is planar.
  const std::string path = dir + "/tiny.relations";
  write_file(path, "1 2 0.1 0.2 1e-10 -1e-9 0 0.3\r\n");
  const RelationsFile file = load_relations(path);
  ASSERT_EQ(file.relations.size(), 1U);
  expect_same(file.relations[0], Relation{1.0, 2.0, Pose2(0.1, 0.2, 0.3)});
  EXPECT_THROW((void)load_relations(dir + "/missing.relations"), IoError);
}

TEST(RelationsIntel, CorruptedCopyWithBadZ) {
  if (!fs::exists(kIntelRelations)) GTEST_SKIP() << "real data not found at " << kIntelRelations;
  const std::string dir = tmp_dir("relations");
  std::vector<std::string> lines = lines_of(kIntelRelations);
  ASSERT_EQ(lines.size(), 2984U);
  // Line 1000: z 0.000000 -> 0.250000; line 2500 loses its yaw.
  std::string& z_line = lines[999];
  const std::size_t z = z_line.find(" 0.000000 0.000000 0.000000 ");
  ASSERT_NE(z, std::string::npos);
  z_line.replace(z, 9, " 0.250000");
  lines[2499] = lines[2499].substr(0, lines[2499].rfind(' '));
  const std::string path = dir + "/intel.relations";
  {
    std::ofstream out(path);
    for (const std::string& l : lines) out << l << '\n';
  }
  EXPECT_EQ(message_of(path), path +
                                  ":1000: z: expected 0 (a planar relation: z, roll and pitch 0 "
                                  "within 1e-9), got '0.250000'");
  RelationsOptions o;
  o.skip_malformed = true;
  const RelationsFile file = load_relations(path, o);
  EXPECT_EQ(file.malformed_lines, (std::vector<std::size_t>{1000, 2500}));
  const RelationsFile original = load_relations(kIntelRelations);
  ASSERT_EQ(file.relations.size(), 2982U);
  std::size_t k = 0;
  for (std::size_t j = 0; j < original.relations.size(); ++j) {
    if (j == 999 || j == 2499) continue;
    expect_same(file.relations[k++], original.relations[j]);
  }
}

TEST(Relations, SaveLoadRoundTripKeepsEveryBit) {
  const std::string dir = tmp_dir("relations");
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::vector<Relation> relations;
  for (int k = 0; k < 200; ++k) {
    relations.push_back({976052896.0 + 13.0 * u(rng), 976052896.0 + 17.0 * u(rng),
                         Pose2(u(rng), u(rng) * 1e-12, u(rng) / 3.0)});
  }
  relations.push_back({0.0, -0.0, Pose2(1e-300, 1e300, std::nextafter(3.0, 4.0))});
  const std::string path = dir + "/round.relations";
  save_relations(path, relations);
  const RelationsFile back = load_relations(path);
  ASSERT_EQ(back.relations.size(), relations.size());
  for (std::size_t k = 0; k < relations.size(); ++k) expect_same(back.relations[k], relations[k]);
  // The file is in the benchmark's layout: 8 fields, z roll pitch written as 0, no exponents.
  for (const std::string& line : lines_of(path)) {
    std::istringstream s(line);
    const std::vector<std::string> f{std::istream_iterator<std::string>(s),
                                     std::istream_iterator<std::string>()};
    ASSERT_EQ(f.size(), 8U) << line;
    EXPECT_EQ(f[4] + f[5] + f[6], "000");
    EXPECT_EQ(line.find_first_of("eE"), std::string::npos) << line;
  }
  // The real file reads back identically after saving.
  if (fs::exists(kIntelRelations)) {
    const RelationsFile intel = load_relations(kIntelRelations);
    save_relations(dir + "/intel.relations", intel.relations);
    const RelationsFile again = load_relations(dir + "/intel.relations");
    ASSERT_EQ(again.relations.size(), intel.relations.size());
    for (std::size_t k = 0; k < intel.relations.size(); ++k) {
      expect_same(again.relations[k], intel.relations[k]);
    }
  }
  EXPECT_THROW(save_relations(path, {Relation{std::nan(""), 1.0, Pose2::Zero()}}), ConfigError);
}

}  // namespace
}  // namespace vdtnav
