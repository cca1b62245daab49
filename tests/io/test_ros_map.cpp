#include "vdtnav/io/ros_map.hpp"

#include <gtest/gtest.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace vdtnav {
namespace {

namespace fs = std::filesystem;
using Cells = std::vector<int>;  // cell values, row j = 0 (bottom) first, x fastest

/// A folder of the running test's own: ctest runs the tests of this file in parallel, and two of
/// them writing no_image.yaml in one folder raced (one read the other's half-written file).
std::string tmp_dir() {
  const fs::path dir = fs::path(VDTNAV_TEST_TMP) / "ros_map" /
                       ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::create_directories(dir);
  return dir.string();
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A binary PGM with rows given top first.
std::string pgm(int w, int h, const std::vector<int>& top_first, int maxval = 255) {
  std::string s = "P5\n# test\n" + std::to_string(w) + " " + std::to_string(h) + "\n" +
                  std::to_string(maxval) + "\n";
  for (int v : top_first) s.push_back(static_cast<char>(v));
  return s;
}

/// Writes NAME.pgm (or the given image) and NAME.yaml with the given extra YAML lines.
std::string write_map(const std::string& name, const std::string& image_bytes,
                      const std::string& yaml_extra, const std::string& image_ext = ".pgm") {
  const std::string dir = tmp_dir();
  write_file(dir + "/" + name + image_ext, image_bytes);
  const std::string yaml = dir + "/" + name + ".yaml";
  write_file(yaml, "image: " + name + image_ext +
                       "\nresolution: 0.1\norigin: [-1.0, 2.0, 0.0]\nnegate: 0\n"
                       "occupied_thresh: 0.65\nfree_thresh: 0.196\n" +
                       yaml_extra);
  return yaml;
}

Cells values(const Grid<std::int8_t, 2>& g) { return Cells(g.values().begin(), g.values().end()); }

// The hand-made 3x2 image, top row first: [0 254 205] over [100 230 60].
const std::vector<int> kTopFirst = {0, 254, 205, 100, 230, 60};

TEST(RosMap, TrinaryValuesAndBottomRowFlip) {
  const RosMap m = load_ros_map(write_map("trinary", pgm(3, 2, kTopFirst), ""));
  ASSERT_EQ(m.cells.size(), Eigen::Vector2i(3, 2));
  // Cell row j = 0 is the image's bottom row: p = (255 - v) / 255 against 0.65 / 0.196.
  EXPECT_EQ(values(m.cells), (Cells{-1, 0, 100, 100, 0, -1}));
  EXPECT_EQ(m.metadata.mode, RosMapMode::kTrinary);
  EXPECT_DOUBLE_EQ(m.cells.resolution(), 0.1);
  // ROS convention: origin is the lower-left corner of cell (0, 0), centres half a cell in.
  EXPECT_NEAR(m.cells.cell_center(Eigen::Vector2i(0, 0)).x(), -0.95, 1e-12);
  EXPECT_NEAR(m.cells.cell_center(Eigen::Vector2i(2, 1)).y(), 2.15, 1e-12);
}

TEST(RosMap, ScaleModeMapsTheBandBetweenThresholdsTo1To99) {
  const RosMap m = load_ros_map(write_map("scale", pgm(3, 2, kTopFirst), "mode: scale\n"));
  // v = 205: p = 0.19608 -> 1 + 98 * 0.00017 = 1; v = 100: p = 0.60784 -> 1 + 98 * 0.90714 = 89.
  EXPECT_EQ(values(m.cells), (Cells{89, 0, 100, 100, 0, 1}));
}

TEST(RosMap, RawModeKeepsValuesUpTo100) {
  const RosMap m = load_ros_map(write_map("raw", pgm(3, 2, kTopFirst), "mode: raw\n"));
  EXPECT_EQ(values(m.cells), (Cells{100, -1, 60, 0, -1, -1}));
}

TEST(RosMap, NegateMakesWhiteOccupied) {
  const std::string yaml = write_map("negate", pgm(3, 2, kTopFirst), "");
  std::string text = read_file(yaml);
  text.replace(text.find("negate: 0"), 9, "negate: true");
  write_file(yaml, text);
  const RosMap m = load_ros_map(yaml);
  EXPECT_TRUE(m.metadata.negate);
  EXPECT_EQ(values(m.cells), (Cells{-1, 100, -1, 0, 100, 100}));
}

TEST(RosMap, ThresholdComparisonsAreStrict) {
  // v = 102 gives p = 0.6 exactly and v = 204 gives p = 0.2 exactly: neither is beyond its
  // threshold, so both are unknown (map_server: occ > occupied_thresh, occ < free_thresh).
  const std::string yaml = write_map("strict", pgm(4, 1, {102, 204, 101, 205}), "");
  std::string text = read_file(yaml);
  text.replace(text.find("occupied_thresh: 0.65"), 21, "occupied_thresh: 0.6");
  text.replace(text.find("free_thresh: 0.196"), 18, "free_thresh: 0.2");
  write_file(yaml, text);
  EXPECT_EQ(values(load_ros_map(yaml).cells), (Cells{-1, -1, 100, 0}));
}

TEST(RosMap, YawAndOriginAreKept) {
  const std::string dir = tmp_dir();
  write_file(dir + "/yaw.pgm", pgm(3, 2, kTopFirst));
  write_file(dir + "/yaw.yaml",
             "image: " + dir +  // absolute image path
                 "/yaw.pgm\nresolution: 0.25\norigin: [1.5, -2.0, 0.5]\nnegate: 0\n"
                 "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  const RosMap m = load_ros_map(dir + "/yaw.yaml");
  EXPECT_EQ(m.image_path, dir + "/yaw.pgm");
  EXPECT_DOUBLE_EQ(m.cells.frame().yaw(), 0.5);
  EXPECT_DOUBLE_EQ(m.metadata.origin.z(), 0.5);
  EXPECT_EQ(m.cells.frame().origin(), Eigen::Vector2d(1.5, -2.0));
  // Cell (0, 0)'s centre is half a cell along the rotated grid axes from the origin.
  const Eigen::Vector2d c = m.cells.cell_center(Eigen::Vector2i(0, 0));
  const double h = 0.125, cy = std::cos(0.5), sy = std::sin(0.5);
  EXPECT_NEAR(c.x(), 1.5 + h * cy - h * sy, 1e-12);
  EXPECT_NEAR(c.y(), -2.0 + h * sy + h * cy, 1e-12);
}

TEST(RosMap, SmallMaxvalIsRescaledLikeMapServer) {
  // maxval 100: 0 -> 0, 50 -> 127, 100 -> 255 (SDL_image's v * 255 / maxval).
  const RosMap m = load_ros_map(write_map("maxval", pgm(3, 1, {0, 50, 100}, 100), "mode: scale\n"));
  EXPECT_EQ(values(m.cells), (Cells{100, 67, 0}));
}

TEST(RosMap, ColourIsTheMeanOfItsChannels) {
  // P6, one row: (255,0,0) -> 85, p = 0.667 occupied; (0,255,255) -> 170, p = 0.333 unknown;
  // (200,250,255) -> 235, free.
  std::string ppm = "P6\n3 1\n255\n";
  for (int v : {255, 0, 0, 0, 255, 255, 200, 250, 255}) ppm.push_back(static_cast<char>(v));
  const RosMap m = load_ros_map(write_map("colour", ppm, "", ".ppm"));
  EXPECT_EQ(values(m.cells), (Cells{100, -1, 0}));
}

TEST(RosMap, AlphaIsAveragedInForTrinaryAndMarksUnknownInScale) {
  // RGBA: transparent white, opaque white, transparent grey 128, opaque grey 128.
  const std::vector<unsigned char> rgba = {255, 255, 255, 0, 255, 255, 255, 255,
                                           128, 128, 128, 0, 128, 128, 128, 255};
  const std::vector<unsigned char> ga = {255, 0, 255, 255, 128, 0, 128, 255};
  const std::string dir = tmp_dir();
  ASSERT_NE(stbi_write_png((dir + "/rgba.png").c_str(), 4, 1, 4, rgba.data(), 16), 0);
  ASSERT_NE(stbi_write_png((dir + "/ga.png").c_str(), 4, 1, 2, ga.data(), 8), 0);
  for (const std::string name : {"rgba", "ga"}) {
    SCOPED_TRACE(name);
    const std::string png = read_file(dir + "/" + name + ".png");
    // Trinary: v = (r + g + b + a) / 4, so transparent white = 191 -> p = 0.25 -> unknown,
    // opaque grey = 159.75 -> p = 0.37 -> unknown, transparent grey = 96 -> p = 0.62 -> unknown.
    const RosMap t = load_ros_map(write_map(name + "_t", png, "", ".png"));
    EXPECT_EQ(values(t.cells), (Cells{-1, 0, -1, -1}));
    // Scale: v = mean of colour; alpha 0 only makes the in-between band unknown.
    const RosMap s = load_ros_map(write_map(name + "_s", png, "mode: scale\n", ".png"));
    EXPECT_EQ(values(s.cells), (Cells{0, 0, -1, 66}));
  }
}

TEST(RosMap, SaveLoadRoundTripIsIdentical) {
  Grid<std::int8_t, 2> g(Eigen::Vector2i(37, 23),
                         GridFrame<2>(0.05, Eigen::Vector2d(-12.345, 6.789), -0.3));
  std::mt19937 rng(7);
  const std::int8_t choices[3] = {kRosUnknown, kRosFree, kRosOccupied};
  for (auto& v : g.values()) v = choices[rng() % 3];
  const std::string prefix = tmp_dir() + "/saved";
  save_ros_map(prefix, g);
  const RosMap m = load_ros_map(prefix + ".yaml");
  EXPECT_EQ(m.cells.size(), g.size());
  EXPECT_EQ(m.cells.values(), g.values());
  EXPECT_EQ(m.cells.resolution(), 0.05);  // exact, not 17-digit noise
  EXPECT_EQ(m.cells.frame().origin(), g.frame().origin());
  EXPECT_EQ(m.cells.frame().yaw(), -0.3);
  EXPECT_EQ(m.image_path, prefix + ".pgm");
  // map_saver's grey levels: occupied black, free 254, unknown 205; top row first.
  const std::string img = read_file(prefix + ".pgm");
  const unsigned char first = static_cast<unsigned char>(img[img.size() - 37 * 23]);
  const int top_left = g(Eigen::Vector2i(0, 22));
  EXPECT_EQ(first, top_left == 100 ? 0 : top_left == 0 ? 254 : 205);
}

TEST(RosMap, OccupancyIsAtLeast65AndUnknownIsFree) {
  Grid<std::int8_t, 2> g(Eigen::Vector2i(5, 1), GridFrame<2>(0.1, Eigen::Vector2d(1, 2)));
  g.values() = {-1, 0, 64, 65, 100};
  const OccupancyGrid<2> o = occupancy(g);
  EXPECT_EQ(o.values(), (std::vector<std::uint8_t>{0, 0, 0, 1, 1}));
  EXPECT_EQ(o.frame().origin(), g.frame().origin());
}

// ---------------------------------------------------------------- malformed input

struct BadYaml {
  const char* name;
  std::string yaml;  // full YAML text; image "good.pgm" exists next to it
  std::size_t line;  // expected line in the message (0: not checked)
  const char* what;  // expected substring
};

TEST(RosMap, EveryMalformedYamlNamesFileLineAndWhatWasExpected) {
  const std::string dir = tmp_dir();
  write_file(dir + "/good.pgm", pgm(3, 2, kTopFirst));
  const std::string ok_tail = "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  const std::string head = "image: good.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
  const std::vector<BadYaml> cases = {
      {"no_resolution", "image: good.pgm\norigin: [0, 0, 0]\n" + ok_tail, 1,
       "missing key 'resolution'"},
      {"no_image", "resolution: 0.05\norigin: [0, 0, 0]\n" + ok_tail, 1, "missing key 'image'"},
      {"no_negate", head + "occupied_thresh: 0.65\nfree_thresh: 0.196\n", 1,
       "missing key 'negate'"},
      {"res_text", "image: good.pgm\nresolution: fine\norigin: [0, 0, 0]\n" + ok_tail, 2,
       "key 'resolution': expected a number, got 'fine'"},
      {"res_zero", "image: good.pgm\nresolution: 0\norigin: [0, 0, 0]\n" + ok_tail, 2,
       "expected a finite number > 0"},
      {"res_neg", "image: good.pgm\nresolution: -0.05\norigin: [0, 0, 0]\n" + ok_tail, 2,
       "expected a finite number > 0"},
      {"res_nan", "image: good.pgm\nresolution: .nan\norigin: [0, 0, 0]\n" + ok_tail, 2,
       "expected a finite number > 0"},
      {"origin_2", "image: good.pgm\nresolution: 0.05\norigin: [0, 0]\n" + ok_tail, 3,
       "expected a sequence [x, y, yaw] of 3 numbers, got 2 elements"},
      {"origin_scalar", "image: good.pgm\nresolution: 0.05\norigin: 4\n" + ok_tail, 3,
       "expected a sequence [x, y, yaw] of 3 numbers"},
      {"origin_text", "image: good.pgm\nresolution: 0.05\norigin: [0, a, 0]\n" + ok_tail, 3,
       "key 'origin': expected a number, got 'a'"},
      {"negate_text", head + "negate: maybe\noccupied_thresh: 0.65\nfree_thresh: 0.196\n", 4,
       "key 'negate': expected 0, 1, true or false"},
      {"occ_big", head + "negate: 0\noccupied_thresh: 1.5\nfree_thresh: 0.196\n", 5,
       "key 'occupied_thresh': expected a number in [0, 1], got '1.5'"},
      {"free_neg", head + "negate: 0\noccupied_thresh: 0.65\nfree_thresh: -0.1\n", 6,
       "key 'free_thresh': expected a number in [0, 1]"},
      {"free_above", head + "negate: 0\noccupied_thresh: 0.5\nfree_thresh: 0.7\n", 6,
       "free_thresh (0.7) must be below occupied_thresh (0.5)"},
      {"mode", head + ok_tail + "mode: fancy\n", 7,
       "unknown mode 'fancy': expected trinary, scale or raw"},
      {"syntax", "image: good.pgm\nresolution: 0.05\norigin: [0, 0, 0\n" + ok_tail, 0,
       "YAML syntax error"},
      {"not_map", "- image\n- good.pgm\n", 1, "expected a YAML mapping"},
      {"image_seq", "image: [a, b]\nresolution: 0.05\norigin: [0, 0, 0]\n" + ok_tail, 1,
       "key 'image': expected a string, got a sequence"},
  };
  for (const BadYaml& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/" + c.name + ".yaml";
    write_file(path, c.yaml);
    try {
      (void)load_ros_map(path);
      ADD_FAILURE() << "no error";
    } catch (const FormatError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(e.file(), path);
      EXPECT_NE(msg.find(path), std::string::npos) << msg;
      EXPECT_NE(msg.find(c.what), std::string::npos) << msg;
      if (c.line > 0) {
        EXPECT_EQ(e.line(), c.line) << msg;
        EXPECT_NE(msg.find(path + ":" + std::to_string(c.line) + ": "), std::string::npos) << msg;
      } else {
        EXPECT_GT(e.line(), 0U) << msg;
      }
    }
  }
}

TEST(RosMap, MissingFilesAreIoErrorsNamingTheFile) {
  const std::string dir = tmp_dir();
  const std::string no_yaml = dir + "/does_not_exist.yaml";
  try {
    (void)load_ros_map(no_yaml);
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(no_yaml), std::string::npos) << e.what();
  }
  const std::string yaml = dir + "/no_image.yaml";
  write_file(yaml,
             "image: missing.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
             "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  try {
    (void)load_ros_map(yaml);
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(dir + "/missing.pgm"), std::string::npos) << msg;
    EXPECT_NE(msg.find(yaml + ":1"), std::string::npos) << msg;
  }
}

TEST(RosMap, UndecodableImagesAreFormatErrorsNamingTheImage) {
  const std::vector<std::pair<std::string, std::string>> images = {
      {"garbage", "this is not an image"},
      {"ascii_pgm", "P2\n2 1\n255\n0 255\n"},
      {"truncated_pgm", "P5\n3 2\n255\nabc"},
      {"pgm16", "P5\n1 1\n65535\n\xff\xff"},
  };
  const std::vector<std::string> expect = {"cannot decode", "cannot decode",
                                           "truncated image data: expected 6", "maxval 65535"};
  for (std::size_t k = 0; k < images.size(); ++k) {
    SCOPED_TRACE(images[k].first);
    const std::string yaml = write_map(images[k].first, images[k].second, "");
    const std::string image = tmp_dir() + "/" + images[k].first + ".pgm";
    try {
      (void)load_ros_map(yaml);
      ADD_FAILURE() << "no error";
    } catch (const FormatError& e) {
      EXPECT_EQ(e.file(), image);
      EXPECT_NE(std::string(e.what()).find(image), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(expect[k]), std::string::npos) << e.what();
    }
  }
}

// ---------------------------------------------------------------- the real fetch office maps

std::string fetch_dir() { return std::string(VDTNAV_DATA_DIR) + "/ros-maps/fetch-office"; }

/// Independent oracle: map_server's trinary rule on a grey value, thresholds 0.65 / 0.196.
int trinary(double v) {
  const double p = (255.0 - v) / 255.0;
  return p > 0.65 ? 100 : p < 0.196 ? 0 : -1;
}

/// Checks dimensions, pixels and the class counts of a loaded real map against `pixel(col, row)`.
void check_against_image(const RosMap& m, int w, int h,
                         const std::function<double(int, int)>& pixel) {
  ASSERT_EQ(m.cells.size(), Eigen::Vector2i(w, h));
  std::mt19937 rng(3);
  int checked = 0;
  for (int k = 0; k < 2000; ++k) {
    const int col = static_cast<int>(rng() % w), row = static_cast<int>(rng() % h);
    ASSERT_EQ(m.cells(Eigen::Vector2i(col, h - 1 - row)), trinary(pixel(col, row)))
        << "pixel (" << col << ", " << row << ")";
    ++checked;
  }
  EXPECT_EQ(checked, 2000);
  // A SLAM map has all three classes, with walls a small minority.
  std::size_t occ = 0, free = 0, unknown = 0;
  for (std::int8_t v : m.cells.values()) (v == 100 ? occ : v == 0 ? free : unknown)++;
  EXPECT_EQ(occ + free + unknown, m.cells.num_cells());
  EXPECT_GT(occ, 1000U);
  EXPECT_GT(free, occ);
  EXPECT_GT(unknown, 0U);
}

TEST(RosMapRealData, FetchOfficePgm) {
  const std::string yaml = fetch_dir() + "/4_26_15.yaml";
  if (!fs::exists(yaml)) GTEST_SKIP() << "real data not found at " << yaml;
  const RosMap m = load_ros_map(yaml);
  EXPECT_DOUBLE_EQ(m.cells.resolution(), 0.05);
  EXPECT_DOUBLE_EQ(m.cells.frame().origin().x(), -25.367399);
  EXPECT_DOUBLE_EQ(m.cells.frame().origin().y(), -15.544381);
  EXPECT_EQ(m.cells.frame().yaw(), 0.0);
  // Parse the PGM header here, independently: magic, comments, width, height, maxval.
  const std::string img = read_file(fetch_dir() + "/4_26_15.pgm");
  std::istringstream in(img);
  std::string magic, token;
  in >> magic;
  ASSERT_EQ(magic, "P5");
  std::vector<int> fields;
  while (fields.size() < 3 && in >> token) {
    if (token[0] == '#') {
      std::getline(in, token);
      continue;
    }
    fields.push_back(std::stoi(token));
  }
  ASSERT_EQ(fields.size(), 3U);
  ASSERT_EQ(fields[2], 255);
  const int w = fields[0], h = fields[1];
  const std::size_t data = static_cast<std::size_t>(in.tellg()) + 1;
  ASSERT_EQ(img.size(), data + static_cast<std::size_t>(w) * h);
  check_against_image(m, w, h, [&](int col, int row) {
    return static_cast<unsigned char>(img[data + static_cast<std::size_t>(row) * w + col]);
  });
  // The PGM's three grey levels are map_saver's 0 / 205 / 254, so they cover every cell.
  const OccupancyGrid<2> o = occupancy(m);
  for (std::size_t k = 0; k < o.num_cells(); ++k) {
    ASSERT_EQ(o[k], m.cells[k] == 100 ? 1 : 0);
  }
}

TEST(RosMapRealData, FetchOfficeRgbPng) {
  const std::string yaml = fetch_dir() + "/3_1_16_localization.yaml";
  if (!fs::exists(yaml)) GTEST_SKIP() << "real data not found at " << yaml;
  const RosMap m = load_ros_map(yaml);
  EXPECT_DOUBLE_EQ(m.cells.resolution(), 0.05);
  EXPECT_EQ(m.cells.frame().origin(), Eigen::Vector2d(0.0, 0.0));
  // Width and height from the PNG's IHDR chunk (big-endian at bytes 16 and 20).
  const std::string png = read_file(fetch_dir() + "/3_1_16_localization.png");
  ASSERT_GT(png.size(), 24U);
  const auto be32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(png[at + k]);
    return static_cast<int>(v);
  };
  ASSERT_EQ(png.substr(12, 4), "IHDR");
  const int w = be32(16), h = be32(20);
  ASSERT_EQ(png[25], 2) << "expected an RGB PNG";  // colour type
  // Pixels decoded here as plain RGB, averaged as map_server does.
  int x = 0, y = 0, n = 0;
  unsigned char* rgb = stbi_load((fetch_dir() + "/3_1_16_localization.png").c_str(), &x, &y, &n, 3);
  ASSERT_NE(rgb, nullptr);
  ASSERT_EQ(x, w);
  ASSERT_EQ(y, h);
  check_against_image(m, w, h, [&](int col, int row) {
    const unsigned char* p = rgb + 3 * (static_cast<std::size_t>(row) * w + col);
    return (p[0] + p[1] + p[2]) / 3.0;
  });
  stbi_image_free(rgb);
}

}  // namespace
}  // namespace vdtnav
