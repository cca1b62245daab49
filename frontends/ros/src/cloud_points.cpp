// cloud_points: a PointCloud2's bytes as points and per-point times (cloud_points.hpp).

#include "vdtnav/ros/cloud_points.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/point_field.hpp"
#include "vdtnav/core/point_time_fields.hpp"

namespace vdtnav::ros {

namespace {

using point_field::is_float;
using point_field::size_of;
using point_field::value;

}  // namespace

CloudPoints cloud_points(const PointCloud2Msg& m, const std::string& source) {
  const auto fail = [&](const std::string& what) { throw FormatError(source, 0, what); };
  if (m.is_bigendian) fail("PointCloud2 with big-endian data: not read");
  const auto field = [&](const std::string& name) -> std::optional<PointFieldMsg> {
    for (const PointFieldMsg& f : m.fields) {
      if (f.name != name) continue;
      const std::size_t size = size_of(f.datatype);
      if (size == 0) fail("PointCloud2 field '" + name + "' has unknown datatype");
      if (static_cast<std::size_t>(f.offset) + size > m.point_step) {
        fail("PointCloud2 field '" + name + "' lies past point_step " +
             std::to_string(m.point_step));
      }
      return f;
    }
    return std::nullopt;
  };
  const auto fx = field("x"), fy = field("y"), fz = field("z");
  if (!fx || !fy || !fz) {
    std::string names;
    for (const PointFieldMsg& f : m.fields) names += (names.empty() ? "" : ", ") + f.name;
    fail("PointCloud2 without x, y and z fields (it has: " + (names.empty() ? "none" : names) +
         ")");
  }
  for (const auto& f : {*fx, *fy, *fz}) {
    if (!is_float(f.datatype)) fail("PointCloud2 field '" + f.name + "' is not FLOAT32/FLOAT64");
  }
  const std::uint64_t width = m.width, height = m.height;
  if (static_cast<std::uint64_t>(m.point_step) * width > m.row_step) {
    fail("PointCloud2 row_step " + std::to_string(m.row_step) + " < width " +
         std::to_string(width) + " x point_step " + std::to_string(m.point_step));
  }
  if (height > 0 && static_cast<std::uint64_t>(m.row_step) * (height - 1) +
                            static_cast<std::uint64_t>(m.point_step) * width >
                        m.data.size()) {
    fail("PointCloud2 data of " + std::to_string(m.data.size()) + " bytes holds less than " +
         std::to_string(height) + " rows of " + std::to_string(m.row_step) + " bytes");
  }

  // The time field: relative (time, t, offset_time) or absolute (timestamp, time_sec+time_nsec).
  CloudPoints out;
  std::optional<PointFieldMsg> ft, fsec, fnsec;
  bool absolute = false;
  for (const PointTimeField& tf : kPointTimeFields) {  // core/point_time_fields.hpp
    if ((ft = field(tf.name))) {
      out.time_field = tf.name;
      absolute = tf.absolute;
      break;
    }
  }
  if (!ft && (fsec = field("time_sec")) && (fnsec = field("time_nsec"))) {
    out.time_field = "time_sec+time_nsec";
    absolute = true;
  }
  const double header_s = static_cast<double>(m.header.stamp_ns) * 1e-9;

  out.points.reserve(width * height);
  for (std::uint64_t row = 0; row < height; ++row) {
    const std::uint8_t* r = m.data.data() + row * m.row_step;
    for (std::uint64_t col = 0; col < width; ++col) {
      const std::uint8_t* p = r + col * m.point_step;
      const Eigen::Vector3d q(value(p + fx->offset, fx->datatype),
                              value(p + fy->offset, fy->datatype),
                              value(p + fz->offset, fz->datatype));
      if (!q.allFinite()) {
        ++out.dropped_not_finite;
        continue;
      }
      out.points.push_back(q);
      if (ft) {
        const double t = point_time_seconds(value(p + ft->offset, ft->datatype),
                                            !is_float(ft->datatype), absolute);
        out.times.push_back(absolute ? t - header_s : t);
      } else if (fsec) {
        // Absolute seconds + nanoseconds: subtract the header's in integers, then scale.
        const double sec = value(p + fsec->offset, fsec->datatype);
        const double nsec = value(p + fnsec->offset, fnsec->datatype);
        const double header_sec = std::floor(header_s);
        out.times.push_back((sec - header_sec) + (nsec * 1e-9 - (header_s - header_sec)));
      }
    }
  }
  return out;
}

}  // namespace vdtnav::ros
