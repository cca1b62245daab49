// ROS 2 CDR as rmw_fastrtps writes it, through the layouts of message_fields.hpp (the ones the
// decoders read) over a writer of little-endian, aligned primitives.

#include "vdtnav/ros/cdr_writer.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "message_fields.hpp"

// The primitives are copied in host order, which must be CDR's little-endian.
#if defined(__BYTE_ORDER__)
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "cdr_writer.cpp assumes little-endian");
#endif

namespace vdtnav::ros {
namespace {

/// The Io (writing) of message_fields.hpp: appends CDR to bytes behind the encapsulation header.
class CdrWriter {
 public:
  static constexpr bool kWrites = true;

  template <typename T>
  void value(const T& v) {
    static_assert(std::is_arithmetic_v<T>);
    append(&v, 1);
  }
  /// bool: one byte, 0 or 1.
  void value(bool v) { value(static_cast<std::uint8_t>(v ? 1 : 0)); }

  /// uint32 length counting the NUL, the bytes, the NUL (no alignment after).
  void str(const std::string& s) {
    value(static_cast<std::uint32_t>(s.size() + 1));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
    bytes_.push_back(0);
  }

  /// builtin_interfaces/msg/Time: int32 sec; uint32 nanosec in [0, 1e9): floor division.
  void time(std::int64_t ns) {
    std::int64_t sec = ns / 1000000000, nanosec = ns % 1000000000;
    if (nanosec < 0) {
      sec -= 1;
      nanosec += 1000000000;
    }
    value(static_cast<std::int32_t>(sec));
    value(static_cast<std::uint32_t>(nanosec));
  }

  /// std_msgs/msg/Header: builtin_interfaces/msg/Time stamp; string frame_id.
  void header(const Header& h) {
    time(h.stamp_ns);
    str(h.frame_id);
  }

  /// A sequence of messages: its uint32 length (the caller writes the elements).
  template <typename T>
  void size(const std::vector<T>& v, std::size_t /*min_element_bytes*/, const char* /*field*/) {
    value(static_cast<std::uint32_t>(v.size()));
  }

  /// A sequence of primitives: uint32 length, then the elements from an aligned start (aligned
  /// even when empty, as Fast CDR does).
  template <typename T>
  void sequence(const std::vector<T>& v, const char* /*field*/) {
    static_assert(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>);
    value(static_cast<std::uint32_t>(v.size()));
    append(v.data(), v.size());
  }

  /// A fixed array: the elements, no length.
  template <std::size_t N>
  void array(const std::array<double, N>& a) {
    append(a.data(), N);
  }

  [[nodiscard]] std::vector<std::uint8_t> release() { return std::move(bytes_); }

 private:
  /// Little-endian plain CDR, no options; alignment counts from the byte after these four.
  static constexpr std::size_t kEncapsulation = 4;

  /// n elements of T at the next multiple of sizeof(T) after the encapsulation, zero padding.
  template <typename T>
  void append(const T* data, std::size_t n) {
    const std::size_t body = bytes_.size() - kEncapsulation;
    const std::size_t at = kEncapsulation + (body + sizeof(T) - 1) / sizeof(T) * sizeof(T);
    bytes_.resize(at + n * sizeof(T), 0);
    if (n > 0) std::memcpy(bytes_.data() + at, data, n * sizeof(T));
  }

  std::vector<std::uint8_t> bytes_{0x00, 0x01, 0x00, 0x00};
};

/// Writes m with its layout (message_fields.hpp).
template <class Msg>
std::vector<std::uint8_t> encode_with(const Msg& m, void (*layout)(CdrWriter&, const Msg&)) {
  CdrWriter w;
  layout(w, m);
  return w.release();
}

}  // namespace

std::vector<std::uint8_t> encode_cdr(const LaserScanMsg& m) {
  return encode_with(m, fields::laser_scan<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const PointCloud2Msg& m) {
  return encode_with(m, fields::point_cloud2<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const OdometryMsg& m) {
  return encode_with(m, fields::odometry<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const TfMsg& m) {
  return encode_with(m, fields::tf<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const PoseStampedMsg& m) {
  return encode_with(m, fields::pose_stamped<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const PoseWithCovarianceStampedMsg& m) {
  return encode_with(m, fields::pose_with_covariance_stamped<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const ImuMsg& m) {
  return encode_with(m, fields::imu<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const OccupancyGridMsg& m) {
  return encode_with(m, fields::occupancy_grid<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const LifecycleTransitionMsg& m) {
  return encode_with(m, fields::lifecycle_transition<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const LifecycleStateMsg& m) {
  return encode_with(m, fields::lifecycle_state<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const ChangeStateRequestMsg& m) {
  return encode_with(m, fields::change_state_request<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const ChangeStateResponseMsg& m) {
  return encode_with(m, fields::change_state_response<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const GetStateResponseMsg& m) {
  return encode_with(m, fields::get_state_response<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const TransitionEventMsg& m) {
  return encode_with(m, fields::transition_event<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const BondStatusMsg& m) {
  return encode_with(m, fields::bond_status<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const EmptyMsg& m) {
  return encode_with(m, fields::empty<CdrWriter>);
}
std::vector<std::uint8_t> encode_cdr(const SetInitialPoseRequestMsg& m) {
  return encode_with(m, fields::set_initial_pose_request<CdrWriter>);
}

}  // namespace vdtnav::ros
