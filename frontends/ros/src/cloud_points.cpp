// cloud_points: a PointCloud2's bytes as points and per-point times (cloud_points.hpp).

#include "vdtnav/ros/cloud_points.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>

#include "vdtnav/core/error.hpp"

namespace vdtnav::ros {

namespace {

// sensor_msgs/PointField datatypes.
enum : std::uint8_t {
  kInt8 = 1,
  kUint8 = 2,
  kInt16 = 3,
  kUint16 = 4,
  kInt32 = 5,
  kUint32 = 6,
  kFloat32 = 7,
  kFloat64 = 8
};

std::size_t size_of(std::uint8_t type) {
  switch (type) {
    case kInt8:
    case kUint8:
      return 1;
    case kInt16:
    case kUint16:
      return 2;
    case kInt32:
    case kUint32:
    case kFloat32:
      return 4;
    case kFloat64:
      return 8;
    default:
      return 0;
  }
}

template <typename T>
T load(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// The value of a field at p as a double (little-endian, checked by the caller).
double value(const std::uint8_t* p, std::uint8_t type) {
  switch (type) {
    case kInt8:
      return load<std::int8_t>(p);
    case kUint8:
      return load<std::uint8_t>(p);
    case kInt16:
      return load<std::int16_t>(p);
    case kUint16:
      return load<std::uint16_t>(p);
    case kInt32:
      return load<std::int32_t>(p);
    case kUint32:
      return load<std::uint32_t>(p);
    case kFloat32:
      return load<float>(p);
    case kFloat64:
      return load<double>(p);
    default:
      return std::nan("");
  }
}

bool is_float(std::uint8_t type) { return type == kFloat32 || type == kFloat64; }

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
  for (const char* name : {"time", "t", "offset_time", "timestamp"}) {
    if ((ft = field(name))) {
      out.time_field = name;
      absolute = out.time_field == "timestamp";
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
        double t = value(p + ft->offset, ft->datatype);
        if (!is_float(ft->datatype)) t *= 1e-9;  // integer times are nanoseconds
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
