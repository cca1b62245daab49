#include "vdtnav/io/ros_map.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <memory>
#include <system_error>
#include <utility>
#include <vector>

#include <stb/stb_image.h>
#include <yaml-cpp/yaml.h>

namespace vdtnav {
namespace {

namespace fs = std::filesystem;

std::vector<unsigned char> read_bytes(const std::string& path, const std::string& what) {
  // Fuzzing found `image: /`: a directory opens, and reading it throws std::ios_base::failure
  // from the stream buffer past every catch of vdtnav::Error.
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw IoError(path + ": is a directory, expected the " + what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open " + what + ": " + std::strerror(errno));
  try {
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
    if (in.bad()) throw IoError(path + ": cannot read " + what);
    return bytes;
  } catch (const std::ios_base::failure& e) {
    throw IoError(path + ": cannot read " + what + ": " + e.what());
  }
}

// ---------------------------------------------------------------- YAML

/// Typed access to the keys of a map_server YAML, every failure a FormatError at the right line.
class YamlKeys {
 public:
  YamlKeys(std::string file, YAML::Node root) : file_(std::move(file)), root_(std::move(root)) {}

  static std::size_t line(const YAML::Node& n) {  // yaml-cpp counts lines from 0
    return static_cast<std::size_t>(std::max(n.Mark().line, 0)) + 1;
  }
  [[noreturn]] void fail(const YAML::Node& at, const std::string& what) const {
    throw FormatError(file_, line(at), what);
  }
  YAML::Node get(const char* key) const {
    YAML::Node n = root_[key];
    if (!n.IsDefined()) fail(root_, std::string("missing key '") + key + "'");
    return n;
  }
  double number(const YAML::Node& n, const std::string& what) const {
    try {
      if (n.IsScalar()) return n.as<double>();
    } catch (const YAML::Exception&) {
    }
    fail(n, what + ": expected a number, got " + describe(n));
  }
  double number(const char* key) const {
    return number(get(key), std::string("key '") + key + "'");
  }
  std::string string(const char* key) const {
    const YAML::Node n = get(key);
    if (!n.IsScalar() || n.Scalar().empty()) {
      fail(n, std::string("key '") + key + "': expected a string, got " + describe(n));
    }
    return n.Scalar();
  }
  bool flag(const char* key) const {  // map_server reads an int; Nav2 also accepts a boolean
    const YAML::Node n = get(key);
    if (n.IsScalar()) {
      int i = 0;
      bool b = false;
      if (YAML::convert<int>::decode(n, i)) return i != 0;
      if (YAML::convert<bool>::decode(n, b)) return b;
    }
    fail(n, std::string("key '") + key + "': expected 0, 1, true or false, got " + describe(n));
  }
  static std::string describe(const YAML::Node& n) {
    if (n.IsScalar()) return "'" + n.Scalar() + "'";
    return n.IsSequence() ? "a sequence" : n.IsMap() ? "a mapping" : "nothing";
  }

 private:
  std::string file_;
  YAML::Node root_;
};

RosMapMetadata parse_yaml(const std::string& yaml_path, std::size_t* image_line) {
  const std::vector<unsigned char> text = read_bytes(yaml_path, "map YAML");
  YAML::Node root;
  try {
    root = YAML::Load(std::string(text.begin(), text.end()));
  } catch (const YAML::ParserException& e) {
    throw FormatError(yaml_path, static_cast<std::size_t>(std::max(e.mark.line, 0)) + 1,
                      "YAML syntax error: " + e.msg);
  }
  const YamlKeys keys(yaml_path, root);
  if (!root.IsMap()) {
    keys.fail(root, "expected a YAML mapping with the map_server keys (image, resolution, ...)");
  }
  RosMapMetadata m;
  m.image = keys.string("image");
  *image_line = YamlKeys::line(keys.get("image"));

  m.resolution = keys.number("resolution");
  if (!(std::isfinite(m.resolution) && m.resolution > 0.0)) {
    keys.fail(keys.get("resolution"), "key 'resolution': expected a finite number > 0, got " +
                                          YamlKeys::describe(keys.get("resolution")));
  }
  const YAML::Node origin = keys.get("origin");
  if (!origin.IsSequence() || origin.size() != 3) {
    keys.fail(origin, "key 'origin': expected a sequence [x, y, yaw] of 3 numbers, got " +
                          (origin.IsSequence() ? std::to_string(origin.size()) + " elements"
                                               : YamlKeys::describe(origin)));
  }
  for (std::size_t k = 0; k < 3; ++k) {
    m.origin[static_cast<int>(k)] = keys.number(origin[k], "key 'origin'");
    if (!std::isfinite(m.origin[static_cast<int>(k)])) {
      keys.fail(origin[k], "key 'origin': expected finite numbers");
    }
  }
  m.negate = keys.flag("negate");
  for (const char* key : {"occupied_thresh", "free_thresh"}) {
    const double t = keys.number(key);
    if (!(t >= 0.0 && t <= 1.0)) {
      keys.fail(keys.get(key), std::string("key '") + key + "': expected a number in [0, 1], got " +
                                   YamlKeys::describe(keys.get(key)));
    }
    (key[0] == 'o' ? m.occupied_thresh : m.free_thresh) = t;
  }
  if (!(m.free_thresh < m.occupied_thresh)) {
    keys.fail(keys.get("free_thresh"), "free_thresh (" + keys.get("free_thresh").Scalar() +
                                           ") must be below occupied_thresh (" +
                                           keys.get("occupied_thresh").Scalar() + ")");
  }
  if (root["mode"].IsDefined()) {
    const std::string mode = keys.string("mode");
    if (mode == "trinary") {
      m.mode = RosMapMode::kTrinary;
    } else if (mode == "scale") {
      m.mode = RosMapMode::kScale;
    } else if (mode == "raw") {
      m.mode = RosMapMode::kRaw;
    } else {
      keys.fail(keys.get("mode"), "unknown mode '" + mode + "': expected trinary, scale or raw");
    }
  }
  return m;
}

// ---------------------------------------------------------------- image

/// The most cells a map image may have (2^28: 16384 x 16384; its VDT alone would take ~5 GB).
constexpr std::uint64_t kMaxImageCells = std::uint64_t{1} << 28;

/// 8-bit pixels with 1 (grey), 2 (grey, alpha), 3 (RGB) or 4 (RGBA) channels, row 0 at the top.
struct Image {
  int width = 0, height = 0, channels = 0;
  std::unique_ptr<unsigned char, void (*)(void*)> pixels{nullptr, stbi_image_free};
};

/// Binary PGM/PPM: stb_image decodes them but neither rescales maxval < 255 (map_server's
/// SDL_image does), nor byte-swaps 16-bit samples, nor checks that the data is complete. This
/// reads the header (magic, width, height, maxval, '#' comments) to do those checks.
/// \return maxval, or 0 when the bytes are not a binary PNM.
int check_pnm(const std::vector<unsigned char>& b, const std::string& path) {
  if (b.size() < 2 || b[0] != 'P' || (b[1] != '5' && b[1] != '6')) return 0;
  std::size_t pos = 2;
  long field[3] = {0, 0, 0};
  for (long& f : field) {
    for (;;) {  // whitespace and comments
      while (pos < b.size() && std::isspace(b[pos])) ++pos;
      if (pos >= b.size() || b[pos] != '#') break;
      while (pos < b.size() && b[pos] != '\n' && b[pos] != '\r') ++pos;
    }
    const std::size_t start = pos;
    while (pos < b.size() && std::isdigit(b[pos])) {
      f = f * 10 + (b[pos++] - '0');
      // Fuzzing found width x height overflowing: no field may exceed 2^30.
      if (f > (1L << 30)) throw FormatError(path, 0, "PGM/PPM header field too large");
    }
    if (pos == start) throw FormatError(path, 0, "malformed PGM/PPM header");
  }
  if (field[0] < 1 || field[1] < 1) {
    throw FormatError(path, 0, "PGM/PPM width and height must be >= 1");
  }
  ++pos;  // the single whitespace after maxval
  if (field[2] < 1 || field[2] > 255) {
    throw FormatError(path, 0,
                      "PGM/PPM maxval " + std::to_string(field[2]) +
                          " is not supported (expected 1..255, 8-bit samples)");
  }
  // Both < 2^30: the product fits in 64 bits.
  const std::uint64_t need = static_cast<std::uint64_t>(field[0]) *
                             static_cast<std::uint64_t>(field[1]) * (b[1] == '5' ? 1U : 3U);
  const std::uint64_t have = b.size() > pos ? b.size() - pos : 0;
  if (have < need) {
    throw FormatError(path, 0,
                      "truncated image data: expected " + std::to_string(need) +
                          " bytes of pixels after the header, found " + std::to_string(have));
  }
  return static_cast<int>(field[2]);
}

Image decode_image(const std::string& path) {
  const std::vector<unsigned char> bytes = read_bytes(path, "map image");
  const int maxval = check_pnm(bytes, path);
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw FormatError(path, 0, "image file too large");
  }
  // Formats told by their magic bytes only: stb_image also guesses TGA, which has none, and
  // fuzzing found arbitrary bytes read as a TGA of 2 GB.
  const auto starts = [&](std::initializer_list<unsigned char> magic) {
    return bytes.size() >= magic.size() && std::equal(magic.begin(), magic.end(), bytes.begin());
  };
  if (!(maxval > 0 || starts({0x89, 'P', 'N', 'G'}) || starts({'B', 'M'}) ||
        starts({0xFF, 0xD8, 0xFF}))) {
    throw FormatError(
        path, 0, "cannot decode the map image: not a PNG, binary PGM/PPM (P5/P6), BMP or JPEG");
  }
  Image img;
  int w = 0, h = 0, c = 0;
  if (stbi_info_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &c) == 1 &&
      static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) > kMaxImageCells) {
    throw FormatError(path, 0,
                      "map image of " + std::to_string(w) + " x " + std::to_string(h) +
                          " pixels: more than the 2^28 cells a map may have");
  }
  // stbi_load converts 16-bit PNG to 8 bits (v >> 8), as map_server's SDL_image does.
  img.pixels.reset(stbi_load_from_memory(bytes.data(), static_cast<int>(bytes.size()), &img.width,
                                         &img.height, &img.channels, 0));
  if (!img.pixels) {
    throw FormatError(path, 0,
                      std::string("cannot decode the map image (stb_image: ") +
                          stbi_failure_reason() + "); expected a PNG or a binary PGM/PPM");
  }
  if (maxval > 0 && maxval < 255) {  // SDL_image: v * 255 / maxval
    unsigned char* p = img.pixels.get();
    const std::size_t n = static_cast<std::size_t>(img.width) * img.height * img.channels;
    for (std::size_t k = 0; k < n; ++k)
      p[k] = static_cast<unsigned char>(std::min(255, p[k] * 255 / maxval));
  }
  return img;
}

/// ROS 1 map_server's per-pixel rule (image_loader.cpp), see load_ros_map().
std::int8_t cell_value(const unsigned char* px, int channels, const RosMapMetadata& m) {
  const bool alpha = channels == 2 || channels == 4;
  const int colour = channels - (alpha ? 1 : 0);
  // map_server sees grey(+alpha) PNGs as RGB(A) with equal channels; for the average that only
  // matters when alpha is averaged in (trinary), where grey counts three times.
  int sum = colour == 1 ? px[0] : px[0] + px[1] + px[2];
  int n = colour == 1 ? 1 : 3;
  const bool average_alpha = alpha && m.mode == RosMapMode::kTrinary;
  if (average_alpha) {
    sum = (colour == 1 ? 3 * px[0] : sum) + px[channels - 1];
    n = 4;
  }
  double v = sum / static_cast<double>(n);
  if (m.negate) v = 255.0 - v;
  if (m.mode == RosMapMode::kRaw) {
    return v < 101.0 ? static_cast<std::int8_t>(v) : kRosUnknown;  // floor(v) <= 100
  }
  const double occ = (255.0 - v) / 255.0;
  if (occ > m.occupied_thresh) return kRosOccupied;
  if (occ < m.free_thresh) return kRosFree;
  if (m.mode == RosMapMode::kTrinary || (alpha && px[channels - 1] == 0)) return kRosUnknown;
  const double ratio = (occ - m.free_thresh) / (m.occupied_thresh - m.free_thresh);
  return static_cast<std::int8_t>(1.0 + 98.0 * ratio);
}

/// Shortest decimal text that reads back as exactly x.
std::string exact(double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), x);
  return std::string(buf, r.ptr);
}

}  // namespace

RosMap load_ros_map(const std::string& yaml_path) {
  RosMap map;
  std::size_t image_line = 0;
  map.metadata = parse_yaml(yaml_path, &image_line);
  const RosMapMetadata& m = map.metadata;
  const fs::path image(m.image);
  map.image_path =
      image.is_absolute() ? image.string() : (fs::path(yaml_path).parent_path() / image).string();
  // The non-throwing form: fuzzing found a name too long for the file system throwing
  // std::filesystem_error past every catch of vdtnav::Error.
  std::error_code ec;
  if (!fs::exists(map.image_path, ec)) {
    throw IoError(map.image_path + ": map image not found (key 'image' at " + yaml_path + ":" +
                  std::to_string(image_line) + (ec ? "; " + ec.message() : std::string()) + ")");
  }
  const Image img = decode_image(map.image_path);
  map.cells = Grid<std::int8_t, 2>(
      Eigen::Vector2i(img.width, img.height),
      GridFrame<2>(m.resolution, Eigen::Vector2d(m.origin.x(), m.origin.y()), m.origin.z()));
  for (int row = 0; row < img.height; ++row) {
    const unsigned char* px =
        img.pixels.get() + static_cast<std::size_t>(row) * img.width * img.channels;
    const int j = img.height - 1 - row;  // image row 0 is the top of the map
    for (int i = 0; i < img.width; ++i, px += img.channels) {
      map.cells(Eigen::Vector2i(i, j)) = cell_value(px, img.channels, m);
    }
  }
  return map;
}

void save_ros_map(const std::string& prefix, const Grid<std::int8_t, 2>& cells) {
  const std::string pgm_path = prefix + ".pgm", yaml_path = prefix + ".yaml";
  const int w = cells.size().x(), h = cells.size().y();
  {
    std::ofstream pgm(pgm_path, std::ios::binary);
    if (!pgm) throw IoError(pgm_path + ": cannot open for writing: " + std::strerror(errno));
    pgm << "P5\n# vdtnav " << exact(cells.resolution()) << " m/pix\n" << w << ' ' << h << "\n255\n";
    std::vector<char> row(static_cast<std::size_t>(w));
    for (int j = h - 1; j >= 0; --j) {  // top row first
      for (int i = 0; i < w; ++i) {
        const std::int8_t c = cells(Eigen::Vector2i(i, j));
        // map_saver's thresholds: free 0..25, occupied >= 65, else unknown.
        row[static_cast<std::size_t>(i)] =
            static_cast<char>(c >= kRosOccupiedThreshold ? 0 : (c >= 0 && c <= 25 ? 254 : 205));
      }
      pgm.write(row.data(), static_cast<std::streamsize>(row.size()));
    }
    if (!pgm.flush()) throw IoError(pgm_path + ": write failed");
  }
  const GridFrame<2>& f = cells.frame();
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "image" << YAML::Value << fs::path(pgm_path).filename().string();
  out << YAML::Key << "mode" << YAML::Value << "trinary";
  out << YAML::Key << "resolution" << YAML::Value << exact(f.resolution());
  out << YAML::Key << "origin" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << exact(f.origin().x()) << exact(f.origin().y()) << exact(f.yaw()) << YAML::EndSeq;
  out << YAML::Key << "negate" << YAML::Value << 0;
  out << YAML::Key << "occupied_thresh" << YAML::Value << "0.65";
  out << YAML::Key << "free_thresh" << YAML::Value << "0.196";
  out << YAML::EndMap;
  std::ofstream yaml(yaml_path);
  if (!yaml) throw IoError(yaml_path + ": cannot open for writing: " + std::strerror(errno));
  yaml << out.c_str() << '\n';
  if (!yaml.flush()) throw IoError(yaml_path + ": write failed");
}

OccupancyGrid<2> occupancy(const Grid<std::int8_t, 2>& cells) {
  OccupancyGrid<2> occ(cells.size(), cells.frame(), 0);
  for (std::size_t k = 0; k < cells.num_cells(); ++k) {
    occ[k] = cells[k] >= kRosOccupiedThreshold ? 1 : 0;
  }
  return occ;
}

OccupancyGrid<2> occupancy(const RosMap& map) { return occupancy(map.cells); }

}  // namespace vdtnav
