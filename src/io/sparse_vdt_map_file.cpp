#include "vdtnav/io/sparse_vdt_map_file.hpp"
#include "binary_file.hpp"
#include "text_fields.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <limits>
#include <memory>
#include <vector>

namespace vdtnav {
namespace {

using binary_file::crc_of;
using binary_file::get;
using binary_file::put;

constexpr char kSparseMagic[8] = {'V', 'D', 'T', 'N', 'A', 'V', 'S', 'P'};
constexpr std::uint64_t kHeaderBytes = 112;
constexpr std::uint64_t kPage = 4096;

std::uint64_t product(const Eigen::Vector3i& n, int add = 0) {
  return static_cast<std::uint64_t>(n.x() + add) * static_cast<std::uint64_t>(n.y() + add) *
         static_cast<std::uint64_t>(n.z() + add);
}

/// The body's layout from the sizes.
struct Layout {
  std::uint64_t coarse, index, payload, end;
};

Layout layout(const Eigen::Vector3i& size, std::uint64_t bricks) {
  const Eigen::Vector3i nb = (size.array() + 7) / 8;
  Layout l;
  l.coarse = kHeaderBytes;
  l.index = l.coarse + 4 * 3 * product(nb);
  l.payload = (l.index + 4 * product(nb) + kPage - 1) / kPage * kPage;
  l.end = l.payload + 4 * std::uint64_t{SparseVdtMap3::kBrickFloats} * bricks;
  return l;
}

}  // namespace

void save_sparse_vdt_map(const std::string& path, const SparseVdtMap3& map) {
  VDTNAV_CHECK((map.size().array() >= 4).all(), "save_sparse_vdt_map: the map is empty");
  const SparseVdtMap3::Bricks& b = map.bricks();
  const Layout l = layout(map.size(), b.num_bricks);
  std::vector<unsigned char> head(kHeaderBytes, 0);
  std::memcpy(head.data(), kSparseMagic, 8);
  put<std::uint32_t>(head, 8, kSparseVdtMapFileVersion);
  put<std::uint32_t>(head, 12, SparseVdtMap3::kBrick);
  for (int d = 0; d < 3; ++d) put<std::int64_t>(head, 16 + 8 * d, map.size()[d]);
  put<double>(head, 40, map.resolution());
  for (int d = 0; d < 3; ++d) put<double>(head, 48 + 8 * d, map.frame().origin()[d]);
  put<double>(head, 72, map.frame().yaw());
  put<double>(head, 80, map.band());
  put<std::uint64_t>(head, 88, b.num_bricks);
  put<std::uint64_t>(head, 96, l.payload);
  put<std::uint32_t>(head, 104, crc_of(head.data(), 104));

  // The body, in order, with its CRC.
  const std::size_t index_bytes = 4 * static_cast<std::size_t>(map.brick_grid_size().prod());
  const std::vector<unsigned char> padding(l.payload - l.index - index_bytes, 0);
  const std::pair<const void*, std::size_t> parts[] = {
      {b.coarse, 3 * index_bytes},
      {b.index, index_bytes},
      {padding.data(), padding.size()},
      {b.coefficients, 4 * std::size_t{SparseVdtMap3::kBrickFloats} * b.num_bricks}};
  std::uint32_t body_crc = crc_of(nullptr, 0);
  for (const auto& [p, n] : parts)
    body_crc = crc_of(static_cast<const unsigned char*>(p), n, body_crc);
  put<std::uint32_t>(head, 108, body_crc);

  std::vector<binary_file::Piece> pieces(std::begin(parts), std::end(parts));
  binary_file::write_atomically(path, head, pieces);
}

SparseVdtMap3 load_sparse_vdt_map(const std::string& path, bool verify_payload) {
  const auto fail = [&path](const std::string& what) { throw FormatError(path, 0, what); };
  const binary_file::MappedFile file = binary_file::map_file(path, "sparse vdtnav map file");
  const std::uint64_t found = file.size;
  std::shared_ptr<const void> mapping = file.owner;
  const unsigned char* h = file.data;

  if (found < 8 || std::memcmp(h, kSparseMagic, 8) != 0) {
    fail("not a sparse vdtnav map file (it does not start with \"VDTNAVSP\")");
  }
  if (found < kHeaderBytes) {
    fail("truncated file: expected at least " + std::to_string(kHeaderBytes) + " bytes, found " +
         std::to_string(found));
  }
  const auto version = get<std::uint32_t>(h, 8);
  if (version != kSparseVdtMapFileVersion) {
    fail("unsupported format version " + std::to_string(version) + " (this build reads version " +
         std::to_string(kSparseVdtMapFileVersion) + ")");
  }
  const std::uint32_t head_crc = crc_of(h, 104), stored_head = get<std::uint32_t>(h, 104);
  if (head_crc != stored_head) {
    fail("header checksum mismatch: stored CRC-32 " + io_text::hex(stored_head) + ", computed " +
         io_text::hex(head_crc) + " (the file is corrupted)");
  }
  if (get<std::uint32_t>(h, 12) != SparseVdtMap3::kBrick) {
    fail("unsupported brick edge " + std::to_string(get<std::uint32_t>(h, 12)) + " (expected 8)");
  }
  Eigen::Vector3i size;
  for (int d = 0; d < 3; ++d) {
    const auto n = get<std::int64_t>(h, 16 + 8 * d);
    if (n < 4 || n > (std::int64_t{1} << 30)) {
      fail("inconsistent header: size along axis " + std::to_string(d) + " is " +
           std::to_string(n) + " (expected >= 4)");
    }
    size[d] = static_cast<int>(n);
  }
  if (product((size.array() + 7) / 8) >= (std::uint64_t{1} << 31)) {
    fail("inconsistent header: 2^31 bricks or more");
  }
  const auto resolution = get<double>(h, 40);
  Eigen::Vector3d origin;
  for (int d = 0; d < 3; ++d) origin[d] = get<double>(h, 48 + 8 * d);
  const auto yaw = get<double>(h, 72), band = get<double>(h, 80);
  if (!(std::isfinite(resolution) && resolution > 0.0) || !origin.allFinite() ||
      !std::isfinite(yaw) || !(std::isfinite(band) && band >= 0.0)) {
    fail("inconsistent header: resolution, origin, yaw or band out of range");
  }
  const auto num_bricks = get<std::uint64_t>(h, 88);
  if (num_bricks > product((size.array() + 7) / 8)) {
    fail("inconsistent header: " + std::to_string(num_bricks) + " bricks, more than the box has");
  }
  const Layout l = layout(size, num_bricks);
  if (get<std::uint64_t>(h, 96) != l.payload) {
    fail("inconsistent header: payload offset " + std::to_string(get<std::uint64_t>(h, 96)) +
         ", expected " + std::to_string(l.payload));
  }
  if (found != l.end) {
    fail(std::string(found < l.end ? "truncated file" : "unexpected data after the map") +
         ": expected " + std::to_string(l.end) + " bytes, found " + std::to_string(found));
  }
  if (verify_payload) {
    const std::uint32_t body = crc_of(h + kHeaderBytes, found - kHeaderBytes);
    const auto stored = get<std::uint32_t>(h, 108);
    if (body != stored) {
      fail("checksum mismatch: stored CRC-32 " + io_text::hex(stored) + ", computed " +
           io_text::hex(body) + " (the file is corrupted)");
    }
  }

  // Nothing is copied: the map points into the mapping, which it keeps alive.
  SparseVdtMap3::Bricks bricks;
  bricks.index = reinterpret_cast<const std::int32_t*>(h + l.index);
  bricks.coefficients = reinterpret_cast<const float*>(h + l.payload);
  bricks.coarse = reinterpret_cast<const std::int32_t*>(h + l.coarse);
  bricks.num_bricks = num_bricks;
  bricks.owner = std::move(mapping);
  try {
    return SparseVdtMap3(GridFrame<3>(resolution, origin, yaw), size, band, std::move(bricks));
  } catch (const ConfigError& e) {
    fail(e.what());
  }
  return {};
}

}  // namespace vdtnav
