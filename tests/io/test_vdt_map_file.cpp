#include "vdtnav/io/vdt_map_file.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace vdtnav {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<unsigned char>;

std::string tmp_path(const std::string& name) {
  // The running test's own folder: ctest runs this file's tests in parallel.
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string own = std::string(test->test_suite_name()) + "." + test->name();
  for (char& c : own) c = c == '/' ? '_' : c;
  const fs::path dir = fs::path(VDTNAV_TEST_TMP) / "vdt_map_file" / own;
  fs::create_directories(dir);
  return (dir / name).string();
}

Bytes read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const Bytes& b) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

/// Independent bitwise CRC-32 (IEEE 802.3, reflected, as zlib's crc32).
std::uint32_t crc32_oracle(const unsigned char* p, std::size_t n) {
  std::uint32_t c = 0xFFFFFFFFU;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320U & (0U - (c & 1U)));
  }
  return ~c;
}

std::uint64_t get_le(const Bytes& b, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int k = n - 1; k >= 0; --k) v = (v << 8) | b[at + static_cast<std::size_t>(k)];
  return v;
}

void put_le(Bytes& b, std::size_t at, std::uint64_t v, int n) {
  for (int k = 0; k < n; ++k)
    b[at + static_cast<std::size_t>(k)] = static_cast<unsigned char>(v >> (8 * k));
}

/// Rewrites the trailing CRC so that only the edited content is wrong.
void fix_crc(Bytes& b) { put_le(b, b.size() - 4, crc32_oracle(b.data(), b.size() - 4), 4); }

template <int Dim>
VdtMap<Dim> make_map() {
  using Index = typename SpaceTraits<Dim>::Index;
  Index size;
  typename SpaceTraits<Dim>::Vector origin;
  for (int d = 0; d < Dim; ++d) {
    size[d] = Dim == 2 ? 24 - 7 * d : 11 - d;
    origin[d] = -1.2 + 0.7 * d;
  }
  OccupancyGrid<Dim> occ(size, GridFrame<Dim>(0.1, origin, 0.25), 0);
  std::mt19937 rng(17);
  for (auto& v : occ.values()) v = rng() % 9 == 0 ? 1 : 0;
  return VdtMap<Dim>::build(occ);
}

template <typename T>
class VdtMapFile : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(VdtMapFile, Dims);

TYPED_TEST(VdtMapFile, RoundTripIsIdentical) {
  constexpr int Dim = TypeParam::value;
  using Vector = typename SpaceTraits<Dim>::Vector;
  const VdtMap<Dim> map = make_map<Dim>();
  const std::string path = tmp_path("round_trip_" + std::to_string(Dim) + "d.vdt");
  save_vdt_map(path, map);
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  const VdtMap<Dim> back = load_vdt_map<Dim>(path);
  EXPECT_EQ(back.size(), map.size());
  EXPECT_EQ(back.resolution(), map.resolution());
  EXPECT_EQ(back.frame().origin(), map.frame().origin());
  EXPECT_EQ(back.frame().yaw(), map.frame().yaw());
  EXPECT_EQ(back.nearest_cells().values(), map.nearest_cells().values());
  EXPECT_EQ(back.field().coefficients(), map.field().coefficients());
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-2.0, 3.0);
  for (int k = 0; k < 300; ++k) {
    Vector p;
    for (int d = 0; d < Dim; ++d) p[d] = u(rng);
    const auto a = map.evaluate(p), b = back.evaluate(p);
    ASSERT_EQ(a.value, b.value);
    ASSERT_EQ(a.jacobian, b.jacobian);
    ASSERT_EQ(a.inside, b.inside);
  }
}

TYPED_TEST(VdtMapFile, LayoutIsTheDocumentedOne) {
  constexpr int Dim = TypeParam::value;
  const VdtMap<Dim> map = make_map<Dim>();
  const std::string path = tmp_path("layout_" + std::to_string(Dim) + "d.vdt");
  save_vdt_map(path, map);
  const Bytes b = read_bytes(path);
  const std::size_t header = 52 + 16 * Dim;
  const std::size_t f = map.nearest_cells().num_cells(), c = map.field().coefficients().size();
  ASSERT_EQ(b.size(), header + 4 * f + 4 * c + 4);
  EXPECT_EQ(std::string(b.begin(), b.begin() + 8), "VDTNAVMP");
  EXPECT_EQ(get_le(b, 8, 4), 1U);
  EXPECT_EQ(get_le(b, 12, 4), static_cast<std::uint64_t>(Dim));
  EXPECT_EQ(get_le(b, 16, 4), 1U);
  for (int d = 0; d < Dim; ++d) {
    EXPECT_EQ(get_le(b, 20 + 8 * d, 8), static_cast<std::uint64_t>(map.size()[d]));
  }
  const std::uint64_t res_bits = get_le(b, 20 + 8 * Dim, 8);
  double res = 0.0;
  std::memcpy(&res, &res_bits, 8);
  EXPECT_EQ(res, 0.1);
  EXPECT_EQ(get_le(b, 36 + 16 * Dim, 8), f);
  EXPECT_EQ(get_le(b, 44 + 16 * Dim, 8), c);
  EXPECT_EQ(static_cast<std::int32_t>(get_le(b, header + 4 * 5, 4)), map.nearest_cells()[5]);
  EXPECT_EQ(get_le(b, b.size() - 4, 4), crc32_oracle(b.data(), b.size() - 4));
}

/// Writes `bytes` to a file, loads it as Dim and checks the FormatError names the file and says
/// `what`.
template <int Dim>
void expect_format_error(const Bytes& bytes, const std::string& name, const std::string& what) {
  SCOPED_TRACE(name);
  const std::string path = tmp_path(name + ".vdt");
  write_bytes(path, bytes);
  try {
    (void)load_vdt_map<Dim>(path);
    ADD_FAILURE() << "no error";
  } catch (const FormatError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), 0U);
    EXPECT_EQ(msg.rfind(path + ": ", 0), 0U) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

TYPED_TEST(VdtMapFile, EveryCorruptionGivesItsDocumentedError) {
  constexpr int Dim = TypeParam::value;
  const VdtMap<Dim> map = make_map<Dim>();
  const std::string path = tmp_path("good_" + std::to_string(Dim) + "d.vdt");
  save_vdt_map(path, map);
  const Bytes good = read_bytes(path);
  const std::size_t header = 52 + 16 * Dim, n = good.size();
  const std::size_t coef0 = header + 4 * map.nearest_cells().num_cells();
  const auto edit = [&](const std::function<void(Bytes&)>& f) {
    Bytes b = good;
    f(b);
    return b;
  };
  const std::string d = std::to_string(Dim) + "d_";

  expect_format_error<Dim>(edit([](Bytes& b) { b[3] = 'X'; }), d + "magic",
                           "not a vdtnav map file");
  expect_format_error<Dim>(Bytes{}, d + "empty", "not a vdtnav map file");
  expect_format_error<Dim>(edit([](Bytes& b) { put_le(b, 8, 2, 4); }), d + "version",
                           "unsupported format version 2 (this build reads version 1)");
  expect_format_error<Dim>(edit([](Bytes& b) { put_le(b, 16, 7, 4); }), d + "kind",
                           "unsupported payload kind 7");
  expect_format_error<Dim>(
      edit([](Bytes& b) { b.resize(b.size() - 10); }), d + "truncated",
      "truncated file: expected " + std::to_string(n) + " bytes, found " + std::to_string(n - 10));
  expect_format_error<Dim>(
      edit([](Bytes& b) { b.resize(30); }), d + "truncated_header",
      "truncated file: expected at least " + std::to_string(header + 4) + " bytes, found 30");
  expect_format_error<Dim>(edit([](Bytes& b) { b.push_back(0); }), d + "trailing",
                           "unexpected data after the map: expected " + std::to_string(n));
  expect_format_error<Dim>(edit([&](Bytes& b) { b[coef0 + 4 * 37 + 1] ^= 0x10; }),
                           d + "bit_flip_payload", "checksum mismatch");
  expect_format_error<Dim>(edit([](Bytes& b) { b[20 + 8 * Dim] ^= 0x01; }),
                           d + "bit_flip_resolution", "checksum mismatch");
  expect_format_error<Dim>(edit([](Bytes& b) { put_le(b, 20, 1, 8); }), d + "size_1",
                           "inconsistent header: size along axis 0 is 1 (expected >= 2)");
  expect_format_error<Dim>(edit([](Bytes& b) { put_le(b, 36 + 16 * Dim, 12, 8); }),
                           d + "feature_count", "inconsistent header: 12 feature cells");
  expect_format_error<Dim>(edit([](Bytes& b) { put_le(b, 44 + 16 * Dim, 12, 8); }),
                           d + "coefficient_count", "inconsistent header: 12 coefficients");
  const double minus_one = -1.0;
  std::uint64_t minus_one_bits = 0;
  std::memcpy(&minus_one_bits, &minus_one, 8);
  expect_format_error<Dim>(edit([&](Bytes& b) { put_le(b, 20 + 8 * Dim, minus_one_bits, 8); }),
                           d + "resolution", "inconsistent header: resolution");
  // Content errors behind a valid checksum.
  const auto& features = map.nearest_cells().values();
  std::size_t free_cell = 0;
  while (features[free_cell] == static_cast<std::int32_t>(free_cell)) ++free_cell;
  expect_format_error<Dim>(edit([&](Bytes& b) {
                             put_le(b, header + 8, static_cast<std::uint64_t>(-5), 4);
                             fix_crc(b);
                           }),
                           d + "feature_negative", "feature of cell 2 is -5, out of range");
  expect_format_error<Dim>(
      edit([&](Bytes& b) {
        put_le(b, header, features.size(), 4);
        fix_crc(b);
      }),
      d + "feature_too_big",
      "feature of cell 0 is " + std::to_string(features.size()) + ", out of range");
  expect_format_error<Dim>(edit([&](Bytes& b) {
                             put_le(b, header + 4 * (free_cell == 0 ? 1 : 0), free_cell, 4);
                             fix_crc(b);
                           }),
                           d + "feature_not_occupied", "which is not an occupied cell");
  expect_format_error<Dim>(edit([&](Bytes& b) {
                             put_le(b, coef0 + 4 * 3, 0x7FC00000U, 4);  // float NaN
                             fix_crc(b);
                           }),
                           d + "coefficient_nan", "coefficient 3 is not finite");
  // The intact file still loads (the edits above worked on copies).
  EXPECT_NO_THROW((void)load_vdt_map<Dim>(path));
}

TEST(VdtMapFile, WrongDimensionSaysWhichIsWhich) {
  const std::string p2 = tmp_path("dim2.vdt"), p3 = tmp_path("dim3.vdt");
  save_vdt_map(p2, make_map<2>());
  save_vdt_map(p3, make_map<3>());
  expect_format_error<2>(read_bytes(p3), "as_2d",
                         "the file holds a 3D map, but a 2D map was requested");
  expect_format_error<3>(read_bytes(p2), "as_3d",
                         "the file holds a 2D map, but a 3D map was requested");
}

TEST(VdtMapFile, MissingFileIsAnIoError) {
  const std::string path = tmp_path("missing.vdt");
  try {
    (void)load_vdt_map<2>(path);
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(VdtMapFile, FailedSaveKeepsThePreviousFile) {
  const std::string path = tmp_path("keep.vdt");
  const VdtMap<2> map = make_map<2>();
  save_vdt_map(path, map);
  const Bytes before = read_bytes(path);
  // A directory where the temporary file should go makes the save fail before the rename.
  fs::create_directories(path + ".tmp");
  EXPECT_THROW(save_vdt_map(path, make_map<2>()), IoError);
  EXPECT_TRUE(fs::is_directory(path + ".tmp"));  // not ours: left alone
  fs::remove(path + ".tmp");
  EXPECT_EQ(read_bytes(path), before);
  EXPECT_THROW(save_vdt_map(tmp_path("no_such_dir/x.vdt"), map), IoError);
  EXPECT_THROW(save_vdt_map(tmp_path("empty.vdt"), VdtMap<2>()), ConfigError);
}

}  // namespace
}  // namespace vdtnav
