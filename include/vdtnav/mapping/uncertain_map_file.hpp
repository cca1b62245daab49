#pragma once
/// \file
/// \brief The uncertain map file (`.umap`): an uncertain VDT map (thesis ch. 5) with the
/// covariance of its control points in factored form (Z's local blocks, Y sparse, and the
/// per-cell quadratic forms a query reads), and the occupancy rendering of the same scans for
/// viewers and for the localizers that read an occupancy grid. Versioned, checksummed, and
/// loaded by memory-mapping: the covariance's arrays are read where they lie in the file.
///
/// Layout, version 1 (little-endian, native float / int32 / double arrays; n control points,
/// m cells in the band, e stored entries of Y; every section padded with zeros to 8 bytes):
///
/// | offset | type      | field                                                          |
/// |--------|-----------|----------------------------------------------------------------|
/// | 0      | char[8]   | magic "VDTNAVUM"                                               |
/// | 8      | u32       | format version (1)                                             |
/// | 12     | u32       | flags: 1 = covariance sections present                         |
/// | 16     | f64       | spacing h of the control points, metres                        |
/// | 24     | f64       | approximation sigma (the per-reading floor), metres            |
/// | 32     | f64[2]    | origin of the lattice (lower corner of cell (0, 0))            |
/// | 48     | i32[2]    | cells per axis                                                 |
/// | 56     | u64       | n, control points (unknowns)                                   |
/// | 64     | u64       | observed points                                                |
/// | 72     | u64       | e, stored entries of Y                                         |
/// | 80     | u32       | columns of Y (3 per scan)                                      |
/// | 84     | u32       | m, cells in the band                                           |
/// | 88     | i32[2]    | occupancy rendering: cells per axis                            |
/// | 96     | f64       | its resolution, metres                                         |
/// | 104    | f64[3]    | its origin x, y and yaw                                        |
/// | 128    | u64       | bytes after the header                                         |
/// | 136    | u32       | CRC-32 (zlib) of bytes [0, 136)                                |
/// | 140    | u32       | CRC-32 of bytes [144, end)                                     |
/// | 144    | u8[cells] | band: 1 where the map is defined (x fastest)                   |
/// |        | f32[cells]| approximation variance per cell, metres^2                      |
/// |        | i32[(cx+3)(cy+3)] | the unknown of each control point of the padded lattice, or -1 |
/// |        | f64[2n]   | control points (c_x, c_y), metres                              |
/// |        | f64[2 obs]| observed points (x, y)                                         |
/// |        | i8[w h]   | occupancy rendering, ROS values -1 / 0..100 (x fastest)        |
/// | flag 1 | f32[196n] | Z's 49 blocks 2 x 2 per control point (CovarianceArrays::z)    |
/// |        | u32[2n+1] | Y's row offsets                                                |
/// |        | u32[e]    | Y's columns                                                    |
/// |        | f32[e]    | Y's values                                                     |
/// |        | f32[408m] | per band cell, cov(DT_v) as quadratic forms (cell_forms)       |

#include <cstdint>
#include <string>

#include "vdtnav/map/grid.hpp"
#include "vdtnav/mapping/uncertain_vdt_map.hpp"

namespace vdtnav::mapping {

/// The format version save_uncertain_map() writes and load_uncertain_map() reads.
inline constexpr std::uint32_t kUncertainMapFileVersion = 1;

/// \brief What an uncertain map file holds.
struct UncertainMapFile {
  UncertainVdtMap map;
  Grid<std::int8_t, 2> occupancy;  ///< the occupancy rendering (ROS values), for viewers
};

/// \brief Writes a map and its occupancy rendering (to `path + ".tmp"`, then renamed over
/// `path`). \throws IoError when the file cannot be written.
void save_uncertain_map(const std::string& path, const UncertainVdtMap& map,
                        const Grid<std::int8_t, 2>& occupancy);

/// \brief Maps a file written by save_uncertain_map() read-only and checks it.
/// \param verify_payload check the CRC-32 of everything after the header (reads every page
///        once); without it the header's CRC and every size are checked.
/// \throws IoError when the file cannot be opened or mapped.
/// \throws FormatError (`file: what`, line 0) for a wrong magic, an unsupported version, an
///         inconsistent header, a file shorter or longer than its header says, a CRC-32 mismatch,
///         or parts that do not make a map (an index out of range, a value not finite).
[[nodiscard]] UncertainMapFile load_uncertain_map(const std::string& path,
                                                  bool verify_payload = true);

/// \return whether the file at `path` starts with the uncertain map file's magic.
[[nodiscard]] bool is_uncertain_map_file(const std::string& path);

}  // namespace vdtnav::mapping
