#pragma once
/// \file
/// \brief A versioned, checksummed binary file for a built `VdtMap<Dim>`, so that a map is built
/// once and loaded in milliseconds.
///
/// Layout, version 1 (all little-endian, no padding; D = dimension):
///
/// | offset       | type      | field                                                         |
/// |--------------|-----------|---------------------------------------------------------------|
/// | 0            | char[8]   | magic "VDTNAVMP"                                              |
/// | 8            | u32       | format version (1)                                            |
/// | 12           | u32       | dimension D (2 or 3)                                          |
/// | 16           | u32       | payload kind: 1 = int32 features + float32 cubic B-spline     |
/// | 20           | i64[D]    | cells per axis n_d (>= 2)                                     |
/// | 20 + 8D      | f64       | resolution (metres, finite, > 0)                              |
/// | 28 + 8D      | f64[D]    | origin: lower corner of cell 0 (SPEC)                         |
/// | 28 + 16D     | f64       | yaw of the grid about z (radians)                             |
/// | 36 + 16D     | u64       | F, number of feature cells = prod n_d                         |
/// | 44 + 16D     | u64       | C, number of coefficients = D prod (n_d + 2)                  |
/// | 52 + 16D     | i32[F]    | features: linear index of each cell's nearest occupied cell   |
/// | ...          | f32[C]    | B-spline coefficients, ghost layer included, channels         |
/// |              |           | interleaved, x fastest (CubicBSplineField::coefficients())   |
/// | end - 4      | u32       | CRC-32 (zlib crc32) of every byte before it                   |
///
/// The header is 84 bytes in 2D and 100 bytes in 3D.

#include <cstdint>
#include <string>

#include "vdtnav/map/vdt_map.hpp"

namespace vdtnav {

/// The format version save_vdt_map() writes and load_vdt_map() reads.
inline constexpr std::uint32_t kVdtMapFileVersion = 1;

/// \brief Writes a built map. The file is written to `path + ".tmp"` and then renamed over
/// `path`, so a failed save leaves any previous file untouched.
/// \throws IoError when the file cannot be written.
/// \throws ConfigError when the map is empty (default-constructed, never built).
template <int Dim>
void save_vdt_map(const std::string& path, const VdtMap<Dim>& map);

/// \brief Reads a map written by save_vdt_map() and checks it.
/// \throws IoError when the file cannot be opened or read.
/// \throws FormatError (`file: what`, line 0) when the magic is wrong ("not a vdtnav map file"),
///         the version is not supported, the file holds another dimension than Dim, the payload
///         kind is unknown, the header is inconsistent (a size < 2, counts that do not match the
///         sizes, resolution not finite and > 0, origin or yaw not finite), the file is truncated
///         or too long (bytes expected vs found), the CRC-32 does not match, a feature is out of
///         range or not an occupied cell, or a coefficient is not finite.
template <int Dim>
[[nodiscard]] VdtMap<Dim> load_vdt_map(const std::string& path);

}  // namespace vdtnav
