#pragma once
/// \file
/// \brief The datatypes of a point cloud's fields as sensor_msgs/PointField numbers them
/// (pcl::PCLPointField uses the same codes): their sizes and little-endian values, for the ROS
/// and the point cloud front ends.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace vdtnav::point_field {

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

/// \return the bytes of a value of `type`, 0 for an unknown type.
[[nodiscard]] inline std::size_t size_of(std::uint8_t type) {
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

[[nodiscard]] inline bool is_float(std::uint8_t type) {
  return type == kFloat32 || type == kFloat64;
}

/// \return the value of `type` at p as a double (the host is little-endian, as the data must
/// be: big-endian clouds are refused by the readers); NaN for an unknown type.
[[nodiscard]] inline double value(const std::uint8_t* p, std::uint8_t type) {
  const auto load = [p](auto v) {
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
  };
  switch (type) {
    case kInt8:
      return load(std::int8_t{});
    case kUint8:
      return load(std::uint8_t{});
    case kInt16:
      return load(std::int16_t{});
    case kUint16:
      return load(std::uint16_t{});
    case kInt32:
      return load(std::int32_t{});
    case kUint32:
      return load(std::uint32_t{});
    case kFloat32:
      return load(float{});
    case kFloat64:
      return load(double{});
    default:
      return std::nan("");
  }
}

}  // namespace vdtnav::point_field
