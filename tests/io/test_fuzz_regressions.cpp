// Every input the fuzzers found a bug with (fuzz/regressions/<target>-<what>.<ext>), read again
// by its parser: a vdtnav::Error naming the file, no crash (these tests also run under ASan and
// UBSan). scripts/fuzz.sh writes new findings to build/fuzz/findings/<target>/.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "vdtnav/core/error.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/ros_map.hpp"

namespace vdtnav {
namespace {

namespace fs = std::filesystem;

std::string tmp_dir() {
  const fs::path dir = fs::path(VDTNAV_TEST_TMP) / "fuzz_regressions" /
                       ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::create_directories(dir);
  return dir.string();
}

/// The message of the vdtnav::Error `f` throws ("" when it throws none).
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(FuzzRegressions, PnmWhoseWidthTimesHeightOverflowsIsAFormatError) {
  // fuzz_ros_map_image: width and height of ten digits each multiplied past 2^63 (UBSan).
  const std::string dir = tmp_dir();
  fs::copy_file(fs::path(VDTNAV_FUZZ_REGRESSIONS) / "ros_map_image-pnm-size-overflow.pgm",
                fs::path(dir) / "map.pgm", fs::copy_options::overwrite_existing);
  {
    std::ofstream y(dir + "/map.yaml");
    y << "image: map.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
         "occupied_thresh: 0.65\nfree_thresh: 0.196\n";
  }
  const std::string msg = error_of([&] { (void)load_ros_map(dir + "/map.yaml"); });
  EXPECT_NE(msg.find("map.pgm"), std::string::npos) << msg;
  EXPECT_NE(msg.find("too large"), std::string::npos) << msg;
}

TEST(FuzzRegressions, ImageNameTooLongForTheFileSystemIsAnIoError) {
  // fuzz_ros_map: `image:` a 400-byte name; std::filesystem::exists threw filesystem_error
  // (ENAMETOOLONG), which no catch of vdtnav::Error stops.
  const std::string dir = tmp_dir();
  fs::copy_file(fs::path(VDTNAV_FUZZ_REGRESSIONS) / "ros_map-image-name-too-long.yaml",
                fs::path(dir) / "map.yaml", fs::copy_options::overwrite_existing);
  const std::string msg = error_of([&] { (void)load_ros_map(dir + "/map.yaml"); });
  EXPECT_NE(msg.find("map.yaml"), std::string::npos) << msg;
}

TEST(FuzzRegressions, BytesWithoutAnImageMagicAreAFormatErrorNotATwoGigabyteTga) {
  // fuzz_ros_map_image: 28 bytes stb_image took for a headerless TGA of ~2 GB (out of memory).
  const std::string dir = tmp_dir();
  fs::copy_file(fs::path(VDTNAV_FUZZ_REGRESSIONS) / "ros_map_image-headerless-tga-2gb.img",
                fs::path(dir) / "map.img", fs::copy_options::overwrite_existing);
  {
    std::ofstream y(dir + "/map.yaml");
    y << "image: map.img\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
         "occupied_thresh: 0.65\nfree_thresh: 0.196\n";
  }
  const std::string msg = error_of([&] { (void)load_ros_map(dir + "/map.yaml"); });
  EXPECT_NE(msg.find("map.img"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not a PNG, binary PGM/PPM"), std::string::npos) << msg;
}

TEST(FuzzRegressions, PngOfMoreCellsThanAMapMayHaveIsRefusedBeforeDecoding) {
  // The same guard for a format with a magic: a PNG header of 20000 x 20000 pixels (4 10^8 cells)
  // and no data is refused from its header, before stb_image allocates.
  const std::string dir = tmp_dir();
  {
    std::ofstream f(dir + "/map.png", std::ios::binary);
    const unsigned char png[] = {0x89, 'P',  'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A, 0,    0, 0,
                                 13,   'I',  'H', 'D', 'R',  0,    0,    0x4E, 0x20, 0, 0,
                                 0x4E, 0x20, 8,   0,   0,    0,    0,    0,    0,    0, 0};
    f.write(reinterpret_cast<const char*>(png), sizeof png);
    std::ofstream y(dir + "/map.yaml");
    y << "image: map.png\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
         "occupied_thresh: 0.65\nfree_thresh: 0.196\n";
  }
  const std::string msg = error_of([&] { (void)load_ros_map(dir + "/map.yaml"); });
  EXPECT_NE(msg.find("map.png"), std::string::npos) << msg;
  EXPECT_NE(msg.find("20000 x 20000"), std::string::npos) << msg;
}

TEST(FuzzRegressions, AnImageThatIsADirectoryIsAnIoError) {
  // fuzz_ros_map (10^6 runs by hand): `image: /` opened, and reading a directory threw
  // std::ios_base::failure from the stream buffer. The same for a CARMEN log.
  const std::string dir = tmp_dir();
  fs::copy_file(fs::path(VDTNAV_FUZZ_REGRESSIONS) / "ros_map-image-is-a-directory.yaml",
                fs::path(dir) / "map.yaml", fs::copy_options::overwrite_existing);
  const std::string msg = error_of([&] { (void)load_ros_map(dir + "/map.yaml"); });
  EXPECT_NE(msg.find("is a directory"), std::string::npos) << msg;
  const std::string log = error_of([&] { (void)load_carmen_log(dir); });
  EXPECT_NE(log.find("is a directory"), std::string::npos) << log;
}

}  // namespace
}  // namespace vdtnav
