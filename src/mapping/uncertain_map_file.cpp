// The uncertain map file (.umap): layout in uncertain_map_file.hpp.
#include "vdtnav/mapping/uncertain_map_file.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <vector>

#include "../io/binary_file.hpp"
#include "../io/text_fields.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::mapping {
namespace umap {

constexpr char kMagic[8] = {'V', 'D', 'T', 'N', 'A', 'V', 'U', 'M'};
constexpr std::uint64_t kHeaderBytes = 144;
constexpr std::uint32_t kHasCovariance = 1;

std::uint64_t pad8(std::uint64_t n) { return (n + 7) / 8 * 8; }

/// The sections' offsets from the header's counts.
struct Layout {
  std::uint64_t active, approx, vars, coef, observed, occupancy, z, y_start, y_col, y_val, forms,
      end;
};

Layout layout(std::uint64_t cells, std::uint64_t padded, std::uint64_t n, std::uint64_t observed,
              std::uint64_t occupancy, bool covariance, std::uint64_t y_entries,
              std::uint64_t band) {
  Layout l{};
  l.active = kHeaderBytes;
  l.approx = l.active + pad8(cells);
  l.vars = l.approx + pad8(4 * cells);
  l.coef = l.vars + pad8(4 * padded);
  l.observed = l.coef + 16 * n;
  l.occupancy = l.observed + 16 * observed;
  l.z = l.occupancy + pad8(occupancy);
  l.end = l.z;
  if (covariance) {
    l.y_start = l.z + 4 * 196 * n;
    l.y_col = l.y_start + pad8(4 * (2 * n + 1));
    l.y_val = l.y_col + pad8(4 * y_entries);
    l.forms = l.y_val + pad8(4 * y_entries);
    l.end = l.forms + 4 * std::uint64_t{3 * UncertainVdtMap::kFormTerms} * band;
  }
  return l;
}

}  // namespace umap

void save_uncertain_map(const std::string& path, const UncertainVdtMap& map,
                        const Grid<std::int8_t, 2>& occupancy) {
  using binary_file::put;
  const UncertainVdtMap::Parts p = map.parts();
  const UncertainVdtMap::CovarianceArrays& c = p.covariance;
  const auto cells = static_cast<std::uint64_t>(p.cells.x()) * p.cells.y();
  const auto n = static_cast<std::uint64_t>(p.coefficients.size() / 2);
  const bool cov = !c.empty();
  const std::uint64_t y_entries = cov ? c.y_row_start[2 * n] : 0;
  const auto occ_cells = static_cast<std::uint64_t>(occupancy.num_cells());
  const umap::Layout l = umap::layout(cells, p.vars.size(), n, p.observed.size(), occ_cells, cov,
                                      y_entries, map.band_cells());
  std::vector<unsigned char> head(umap::kHeaderBytes, 0);
  std::memcpy(head.data(), umap::kMagic, 8);
  put<std::uint32_t>(head, 8, kUncertainMapFileVersion);
  put<std::uint32_t>(head, 12, cov ? umap::kHasCovariance : 0);
  put<double>(head, 16, p.spacing);
  put<double>(head, 24, p.approximation_sigma);
  put<double>(head, 32, p.origin.x());
  put<double>(head, 40, p.origin.y());
  put<std::int32_t>(head, 48, p.cells.x());
  put<std::int32_t>(head, 52, p.cells.y());
  put<std::uint64_t>(head, 56, n);
  put<std::uint64_t>(head, 64, p.observed.size());
  put<std::uint64_t>(head, 72, y_entries);
  put<std::uint32_t>(head, 80, cov ? c.y_columns : 0);
  put<std::uint32_t>(head, 84, static_cast<std::uint32_t>(map.band_cells()));
  put<std::int32_t>(head, 88, occupancy.size().x());
  put<std::int32_t>(head, 92, occupancy.size().y());
  put<double>(head, 96, occupancy.resolution());
  put<double>(head, 104, occupancy.frame().origin().x());
  put<double>(head, 112, occupancy.frame().origin().y());
  put<double>(head, 120, occupancy.frame().yaw());
  put<std::uint64_t>(head, 128, l.end - umap::kHeaderBytes);
  put<std::uint32_t>(head, 136, binary_file::crc_of(head.data(), 136));

  std::vector<float> approx(p.approximation_var);
  approx.resize(cells, 0.0f);
  std::vector<double> observed;
  observed.reserve(2 * p.observed.size());
  for (const auto& q : p.observed) {
    observed.push_back(q.x());
    observed.push_back(q.y());
  }
  const std::vector<unsigned char> zeros(8, 0);
  std::vector<binary_file::Piece> pieces;
  const auto add = [&](const void* data, std::uint64_t bytes) {
    pieces.emplace_back(data, bytes);
    if (bytes % 8 != 0) pieces.emplace_back(zeros.data(), 8 - bytes % 8);
  };
  add(p.active.data(), cells);
  add(approx.data(), 4 * cells);
  add(p.vars.data(), 4 * p.vars.size());
  add(p.coefficients.data(), 8 * p.coefficients.size());
  add(observed.data(), 8 * observed.size());
  add(occupancy.data(), occ_cells);
  if (cov) {
    add(c.z, 4 * 196 * n);
    add(c.y_row_start, 4 * (2 * n + 1));
    add(c.y_column, 4 * y_entries);
    add(c.y_value, 4 * y_entries);
    add(c.cell_forms, 4 * std::uint64_t{3 * UncertainVdtMap::kFormTerms} * map.band_cells());
  }
  std::uint32_t body = binary_file::crc_of(nullptr, 0);
  for (const auto& [d, b] : pieces)
    body = binary_file::crc_of(static_cast<const unsigned char*>(d), b, body);
  put<std::uint32_t>(head, 140, body);
  binary_file::write_atomically(path, head, pieces);
}

bool is_uncertain_map_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  return in.read(magic, 8) && std::memcmp(magic, umap::kMagic, 8) == 0;
}

UncertainMapFile load_uncertain_map(const std::string& path, bool verify_payload) {
  using binary_file::get;
  const auto fail = [&path](const std::string& what) { throw FormatError(path, 0, what); };
  const binary_file::MappedFile f = binary_file::map_file(path, "uncertain map file");
  const unsigned char* h = f.data;
  if (f.size < 8 || std::memcmp(h, umap::kMagic, 8) != 0) {
    fail("not an uncertain map file (it does not start with \"VDTNAVUM\")");
  }
  if (f.size < umap::kHeaderBytes) {
    fail("truncated file: expected at least " + std::to_string(umap::kHeaderBytes) +
         " bytes, found " + std::to_string(f.size));
  }
  const auto version = get<std::uint32_t>(h, 8);
  if (version != kUncertainMapFileVersion) {
    fail("unsupported format version " + std::to_string(version) + " (this build reads version " +
         std::to_string(kUncertainMapFileVersion) + ")");
  }
  const std::uint32_t head_crc = binary_file::crc_of(h, 136);
  if (head_crc != get<std::uint32_t>(h, 136)) {
    fail("header checksum mismatch: stored CRC-32 " + io_text::hex(get<std::uint32_t>(h, 136)) +
         ", computed " + io_text::hex(head_crc) + " (the file is corrupted)");
  }
  const auto flags = get<std::uint32_t>(h, 12);
  if ((flags & ~umap::kHasCovariance) != 0) fail("unknown flags " + std::to_string(flags));
  const bool cov = (flags & umap::kHasCovariance) != 0;
  UncertainVdtMap::Parts p;
  p.spacing = get<double>(h, 16);
  p.approximation_sigma = get<double>(h, 24);
  p.origin = Eigen::Vector2d(get<double>(h, 32), get<double>(h, 40));
  p.cells = Eigen::Vector2i(get<std::int32_t>(h, 48), get<std::int32_t>(h, 52));
  const Eigen::Vector2i occ_size(get<std::int32_t>(h, 88), get<std::int32_t>(h, 92));
  const double occ_res = get<double>(h, 96);
  const Eigen::Vector2d occ_origin(get<double>(h, 104), get<double>(h, 112));
  const double occ_yaw = get<double>(h, 120);
  if (p.cells.x() < 1 || p.cells.y() < 1 || p.cells.x() > (1 << 20) || p.cells.y() > (1 << 20) ||
      occ_size.x() < 1 || occ_size.y() < 1 || occ_size.x() > (1 << 20) ||
      occ_size.y() > (1 << 20) || !(std::isfinite(occ_res) && occ_res > 0.0) ||
      !occ_origin.allFinite() || !std::isfinite(occ_yaw)) {
    fail("inconsistent header: a lattice or occupancy size, resolution or origin out of range");
  }
  const auto cells = static_cast<std::uint64_t>(p.cells.x()) * p.cells.y();
  const auto padded = static_cast<std::uint64_t>(p.cells.x() + 3) * (p.cells.y() + 3);
  const auto n = get<std::uint64_t>(h, 56), n_obs = get<std::uint64_t>(h, 64),
             y_entries = get<std::uint64_t>(h, 72);
  const auto y_columns = get<std::uint32_t>(h, 80), band = get<std::uint32_t>(h, 84);
  const auto occ_cells = static_cast<std::uint64_t>(occ_size.x()) * occ_size.y();
  // Counts that could not fit the file are refused before any offset is computed from them.
  if (n > f.size / 16 || n_obs > f.size / 16 || y_entries > f.size / 8 || band > cells ||
      occ_cells > f.size) {
    fail("inconsistent header: counts larger than the file (" + std::to_string(f.size) + " bytes)");
  }
  const umap::Layout l = umap::layout(cells, padded, n, n_obs, occ_cells, cov, y_entries, band);
  if (get<std::uint64_t>(h, 128) != l.end - umap::kHeaderBytes) {
    fail("inconsistent header: it says " + std::to_string(get<std::uint64_t>(h, 128)) +
         " bytes of body, its counts make " + std::to_string(l.end - umap::kHeaderBytes));
  }
  if (f.size != l.end) {
    fail(std::string(f.size < l.end ? "truncated file" : "unexpected data after the map") +
         ": expected " + std::to_string(l.end) + " bytes, found " + std::to_string(f.size));
  }
  if (verify_payload) {
    const std::uint32_t body =
        binary_file::crc_of(h + umap::kHeaderBytes, f.size - umap::kHeaderBytes);
    if (body != get<std::uint32_t>(h, 140)) {
      fail("checksum mismatch: stored CRC-32 " + io_text::hex(get<std::uint32_t>(h, 140)) +
           ", computed " + io_text::hex(body) + " (the file is corrupted)");
    }
  }
  // The small parts are copied; the covariance's arrays stay in the mapping.
  p.active.assign(h + l.active, h + l.active + cells);
  std::uint64_t in_band = 0;
  for (const char a : p.active) in_band += a != 0;
  if (in_band != band) {
    fail("inconsistent body: " + std::to_string(in_band) + " cells in the band, the header says " +
         std::to_string(band));
  }
  p.approximation_var.resize(cells);
  std::memcpy(p.approximation_var.data(), h + l.approx, 4 * cells);
  p.vars.resize(padded);
  std::memcpy(p.vars.data(), h + l.vars, 4 * padded);
  p.coefficients.resize(2 * n);
  std::memcpy(p.coefficients.data(), h + l.coef, 16 * n);
  p.observed.resize(n_obs);
  for (std::uint64_t k = 0; k < n_obs; ++k) {
    p.observed[k] = Eigen::Vector2d(get<double>(h, l.observed + 16 * k),
                                    get<double>(h, l.observed + 16 * k + 8));
  }
  Grid<std::int8_t, 2> occupancy(occ_size, GridFrame<2>(occ_res, occ_origin, occ_yaw));
  std::memcpy(occupancy.data(), h + l.occupancy, occ_cells);
  if (cov) {
    UncertainVdtMap::CovarianceArrays& c = p.covariance;
    c.z = reinterpret_cast<const float*>(h + l.z);
    c.y_row_start = reinterpret_cast<const std::uint32_t*>(h + l.y_start);
    c.y_column = reinterpret_cast<const std::uint32_t*>(h + l.y_col);
    c.y_value = reinterpret_cast<const float*>(h + l.y_val);
    c.y_columns = y_columns;
    c.cell_forms = reinterpret_cast<const float*>(h + l.forms);
    c.owner = f.owner;
    if (c.y_row_start[2 * n] != y_entries) {
      fail("inconsistent body: Y's row offsets end at " + std::to_string(c.y_row_start[2 * n]) +
           ", the header says " + std::to_string(y_entries) + " entries");
    }
  }
  try {
    return UncertainMapFile{UncertainVdtMap::assemble(std::move(p)), std::move(occupancy)};
  } catch (const ConfigError& e) {
    throw FormatError(path, 0, e.what());
  }
}

}  // namespace vdtnav::mapping
