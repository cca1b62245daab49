#pragma once
/// \file
/// \brief A versioned, checksummed binary file for a `SparseVdtMap3`, loaded by memory-mapping
/// everything after its header read-only (POSIX mmap): nothing is copied, pages are read when a
/// query (or the checksum) touches them, and processes that open the same file share them.
///
/// Layout, version 1 (little-endian, native float/int32 arrays; nb = ceil(n / 8) bricks per axis,
/// B = allocated bricks):
///
/// | offset | type        | field                                                             |
/// |--------|-------------|-------------------------------------------------------------------|
/// | 0      | char[8]     | magic "VDTNAVSP"                                                  |
/// | 8      | u32         | format version (1)                                                |
/// | 12     | u32         | brick edge in voxels (8)                                          |
/// | 16     | i64[3]      | voxels per axis n_d (>= 4)                                        |
/// | 40     | f64         | resolution (metres, finite, > 0)                                  |
/// | 48     | f64[3]      | origin: lower corner of voxel 0 (SPEC)                            |
/// | 72     | f64         | yaw of the grid about z (radians)                                 |
/// | 80     | f64         | band (voxels, SparseVdtMapOptions::band)                          |
/// | 88     | u64         | B, allocated bricks                                               |
/// | 96     | u64         | offset of the brick payload (a multiple of 4096)                  |
/// | 104    | u32         | CRC-32 (zlib) of bytes [0, 104)                                   |
/// | 108    | u32         | CRC-32 of bytes [112, end)                                        |
/// | 112    | i32[3 prod nb]    | coarse level: surface voxel (x, y, z) nearest to each brick |
/// | ...    | i32[prod nb]      | brick index: slot of each brick (x fastest), or -1          |
/// | ...    | zeros             | up to the payload offset                                    |
/// | payload| f32[1536 B]       | per slot 8^3 nodes (x fastest) x (DT_x, DT_y, DT_z)         |

#include <string>

#include "vdtnav/map/sparse_vdt_map.hpp"

namespace vdtnav {

/// The format version save_sparse_vdt_map() writes and load_sparse_vdt_map() reads.
inline constexpr std::uint32_t kSparseVdtMapFileVersion = 1;

/// \brief Writes a built map (to `path + ".tmp"`, then renamed over `path`).
/// \throws IoError when the file cannot be written; ConfigError when the map is empty.
void save_sparse_vdt_map(const std::string& path, const SparseVdtMap3& map);

/// \brief Maps a file written by save_sparse_vdt_map() read-only and checks it.
/// \param verify_payload check the CRC-32 of the coarse level, index and bricks (reads every
///        page once); without it only the header's CRC and every size are checked.
/// \throws IoError when the file cannot be opened or mapped.
/// \throws FormatError (`file: what`, line 0) for a wrong magic, an unsupported version or brick
///         edge, an inconsistent header, a file shorter or longer than its header says, a CRC-32
///         mismatch, or a brick index or coarse voxel out of range.
[[nodiscard]] SparseVdtMap3 load_sparse_vdt_map(const std::string& path,
                                                bool verify_payload = true);

}  // namespace vdtnav
