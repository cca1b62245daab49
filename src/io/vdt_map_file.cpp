#include "vdtnav/io/vdt_map_file.hpp"
#include "binary_file.hpp"
#include "text_fields.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include <zlib.h>

namespace vdtnav {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'V', 'D', 'T', 'N', 'A', 'V', 'M', 'P'};
constexpr std::uint32_t kPayloadFeaturesBSpline = 1;
constexpr std::size_t kChunk = std::size_t{1} << 16;  // array elements converted per write/read

constexpr std::uint64_t header_bytes(std::uint64_t dim) { return 52 + 16 * dim; }

template <typename To, typename From>
To bit_cast(const From& x) {
  static_assert(sizeof(To) == sizeof(From));
  To t;
  std::memcpy(&t, &x, sizeof(To));
  return t;
}

std::uint32_t crc_update(std::uint32_t crc, const unsigned char* p, std::size_t n) {
  return binary_file::crc_of(p, n, crc);
}

/// Little-endian writer that keeps the CRC-32 of everything written.
class Writer {
 public:
  explicit Writer(std::ostream& out) : out_(out) {}
  void raw(const void* p, std::size_t n) {
    out_.write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
    crc_ = crc_update(crc_, static_cast<const unsigned char*>(p), n);
  }
  void le(std::uint64_t v, int bytes) {
    unsigned char b[8];
    for (int k = 0; k < bytes; ++k) b[k] = static_cast<unsigned char>(v >> (8 * k));
    raw(b, static_cast<std::size_t>(bytes));
  }
  void f64(double x) { le(bit_cast<std::uint64_t>(x), 8); }
  template <typename T>  // int32 or float
  void array(const std::vector<T>& v) {
    std::vector<unsigned char> buf;
    for (std::size_t i = 0; i < v.size(); i += kChunk) {
      const std::size_t m = std::min(kChunk, v.size() - i);
      buf.resize(4 * m);
      for (std::size_t k = 0; k < m; ++k) {
        const auto u = bit_cast<std::uint32_t>(v[i + k]);
        for (int b = 0; b < 4; ++b) buf[4 * k + b] = static_cast<unsigned char>(u >> (8 * b));
      }
      raw(buf.data(), buf.size());
    }
  }
  [[nodiscard]] std::uint32_t crc() const { return crc_; }

 private:
  std::ostream& out_;
  std::uint32_t crc_ = static_cast<std::uint32_t>(crc32(0L, Z_NULL, 0));
};

/// Little-endian reader that keeps the CRC-32 of everything read. The caller has checked the file
/// length, so a short read here is an I/O failure.
class Reader {
 public:
  Reader(std::istream& in, const std::string& path) : in_(in), path_(path) {}
  void raw(void* p, std::size_t n) {
    if (!in_.read(static_cast<char*>(p), static_cast<std::streamsize>(n))) {
      throw IoError(path_ + ": read error");
    }
    crc_ = crc_update(crc_, static_cast<const unsigned char*>(p), n);
  }
  std::uint64_t le(int bytes) {
    unsigned char b[8];
    raw(b, static_cast<std::size_t>(bytes));
    std::uint64_t v = 0;
    for (int k = bytes - 1; k >= 0; --k) v = (v << 8) | b[k];
    return v;
  }
  double f64() { return bit_cast<double>(le(8)); }
  template <typename T>
  void array(std::vector<T>& v, std::size_t n) {
    v.resize(n);
    std::vector<unsigned char> buf;
    for (std::size_t i = 0; i < n; i += kChunk) {
      const std::size_t m = std::min(kChunk, n - i);
      buf.resize(4 * m);
      raw(buf.data(), buf.size());
      for (std::size_t k = 0; k < m; ++k) {
        std::uint32_t u = 0;
        for (int b = 3; b >= 0; --b) u = (u << 8) | buf[4 * k + b];
        v[i + k] = bit_cast<T>(u);
      }
    }
  }
  [[nodiscard]] std::uint32_t crc() const { return crc_; }

 private:
  std::istream& in_;
  const std::string& path_;
  std::uint32_t crc_ = static_cast<std::uint32_t>(crc32(0L, Z_NULL, 0));
};

}  // namespace

template <int Dim>
void save_vdt_map(const std::string& path, const VdtMap<Dim>& map) {
  VDTNAV_CHECK((map.size().array() >= 2).all(), "save_vdt_map: the map is empty (not built)");
  binary_file::write_atomically(path, [&map](std::ofstream& out) {
    const GridFrame<Dim>& f = map.frame();
    Writer w(out);
    w.raw(kMagic, sizeof(kMagic));
    w.le(kVdtMapFileVersion, 4);
    w.le(Dim, 4);
    w.le(kPayloadFeaturesBSpline, 4);
    for (int d = 0; d < Dim; ++d) w.le(static_cast<std::uint64_t>(map.size()[d]), 8);
    w.f64(f.resolution());
    for (int d = 0; d < Dim; ++d) w.f64(f.origin()[d]);
    w.f64(f.yaw());
    w.le(map.nearest_cells().values().size(), 8);
    w.le(map.field().coefficients().size(), 8);
    w.array(map.nearest_cells().values());
    w.array(map.field().coefficients());
    w.le(w.crc(), 4);
  });
}

template <int Dim>
VdtMap<Dim> load_vdt_map(const std::string& path) {
  using Index = typename SpaceTraits<Dim>::Index;
  using Vector = typename SpaceTraits<Dim>::Vector;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open vdtnav map file: " + std::strerror(errno));
  in.seekg(0, std::ios::end);
  const auto found = static_cast<std::uint64_t>(in.tellg());
  in.seekg(0, std::ios::beg);
  const auto fail = [&path](const std::string& what) { throw FormatError(path, 0, what); };
  const auto truncated = [&](std::uint64_t expected, const char* at_least) {
    fail("truncated file: expected " + std::string(at_least) + std::to_string(expected) +
         " bytes, found " + std::to_string(found));
  };

  Reader r(in, path);
  char magic[sizeof(kMagic)] = {};
  const std::size_t magic_bytes = static_cast<std::size_t>(std::min<std::uint64_t>(found, 8));
  r.raw(magic, magic_bytes);
  if (std::memcmp(magic, kMagic, magic_bytes) != 0 || found == 0) {
    fail("not a vdtnav map file (it does not start with \"VDTNAVMP\")");
  }
  if (found < 20) truncated(header_bytes(Dim) + 4, "at least ");
  const std::uint64_t version = r.le(4), dim = r.le(4), kind = r.le(4);
  if (version != kVdtMapFileVersion) {
    fail("unsupported format version " + std::to_string(version) + " (this build reads version " +
         std::to_string(kVdtMapFileVersion) + ")");
  }
  if (dim != Dim) {
    fail("the file holds a " + std::to_string(dim) + "D map, but a " + std::to_string(Dim) +
         "D map was requested");
  }
  if (kind != kPayloadFeaturesBSpline) {
    fail("unsupported payload kind " + std::to_string(kind) +
         " (this build reads kind 1: int32 features + float32 cubic B-spline coefficients)");
  }
  if (found < header_bytes(Dim) + 4) truncated(header_bytes(Dim) + 4, "at least ");

  Index size;
  std::uint64_t cells = 1, padded = Dim;
  for (int d = 0; d < Dim; ++d) {
    const auto n = static_cast<std::int64_t>(r.le(8));
    if (n < 2 || n > std::numeric_limits<std::int32_t>::max()) {
      fail("inconsistent header: size along axis " + std::to_string(d) + " is " +
           std::to_string(n) + " (expected >= 2)");
    }
    size[d] = static_cast<int>(n);
    cells *= static_cast<std::uint64_t>(n);
    padded *= static_cast<std::uint64_t>(n + 2);
    if (cells >= (std::uint64_t{1} << 31)) fail("inconsistent header: 2^31 cells or more");
  }
  const double resolution = r.f64();
  if (!(std::isfinite(resolution) && resolution > 0.0)) {
    fail("inconsistent header: resolution " + std::to_string(resolution) +
         " is not finite and > 0");
  }
  Vector origin;
  for (int d = 0; d < Dim; ++d) origin[d] = r.f64();
  const double yaw = r.f64();
  if (!origin.allFinite() || !std::isfinite(yaw)) {
    fail("inconsistent header: origin or yaw is not finite");
  }
  const std::uint64_t num_features = r.le(8), num_coefficients = r.le(8);
  if (num_features != cells) {
    fail("inconsistent header: " + std::to_string(num_features) +
         " feature cells, but the sizes give " + std::to_string(cells));
  }
  if (num_coefficients != padded) {
    fail("inconsistent header: " + std::to_string(num_coefficients) +
         " coefficients, but the sizes give " + std::to_string(padded));
  }
  const std::uint64_t expected = header_bytes(Dim) + 4 * (cells + padded) + 4;
  if (found < expected) truncated(expected, "");
  if (found > expected) {
    fail("unexpected data after the map: expected " + std::to_string(expected) + " bytes, found " +
         std::to_string(found));
  }

  Grid<std::int32_t, Dim> nearest(size, GridFrame<Dim>(resolution, origin, yaw));
  std::vector<float> coefficients;
  r.array(nearest.values(), cells);
  r.array(coefficients, padded);
  const std::uint32_t computed = r.crc();
  const auto stored = static_cast<std::uint32_t>(r.le(4));
  if (stored != computed) {
    fail("checksum mismatch: stored CRC-32 " + io_text::hex(stored) + ", computed " +
         io_text::hex(computed) + " (the file is corrupted)");
  }
  const std::vector<std::int32_t>& features = nearest.values();
  for (std::size_t c = 0; c < features.size(); ++c) {
    if (features[c] < 0 || static_cast<std::uint64_t>(features[c]) >= cells) {
      fail("feature of cell " + std::to_string(c) + " is " + std::to_string(features[c]) +
           ", out of range [0, " + std::to_string(cells) + ")");
    }
  }
  for (std::size_t c = 0; c < features.size(); ++c) {
    const std::int32_t f = features[c];
    if (features[static_cast<std::size_t>(f)] != f) {  // an occupied cell is its own feature
      fail("feature of cell " + std::to_string(c) + " is cell " + std::to_string(f) +
           ", which is not an occupied cell");
    }
  }
  const auto bad = std::find_if(coefficients.begin(), coefficients.end(),
                                [](float c) { return !std::isfinite(c); });
  if (bad != coefficients.end()) {
    fail("coefficient " + std::to_string(bad - coefficients.begin()) + " is not finite");
  }
  return VdtMap<Dim>(std::move(nearest),
                     VdtMap<Dim>::Field::from_coefficients(size, std::move(coefficients)));
}

template void save_vdt_map<2>(const std::string&, const VdtMap<2>&);
template void save_vdt_map<3>(const std::string&, const VdtMap<3>&);
template VdtMap<2> load_vdt_map<2>(const std::string&);
template VdtMap<3> load_vdt_map<3>(const std::string&);

}  // namespace vdtnav
