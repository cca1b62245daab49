#pragma once
// A Fast DDS type whose samples are serialized messages as they are: the CDR bytes with their
// encapsulation header (what rmw writes into a rosbag2, what cdr_writer.hpp encodes). The type
// carries a ROS 2 type's DDS name (dds_type_name()) and no type object or type information, as
// rmw_fastrtps registers its types: remote endpoints match on the name. Keyless, unbounded.
#include <fastdds/rtps/common/InstanceHandle.h>
#include <fastdds/rtps/common/SerializedPayload.h>
#include <fastdds/dds/topic/TopicDataType.hpp>

#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

namespace vdtnav::ros2 {

/// One sample: CDR with its 4-byte encapsulation header.
struct RawCdrSample {
  std::vector<std::uint8_t> cdr;
};

class RawCdrType final : public eprosima::fastdds::dds::TopicDataType {
 public:
  explicit RawCdrType(const std::string& dds_name) {
    setName(dds_name.c_str());
    m_typeSize = 4096;  // the payloads' first allocation; they grow (REALLOC memory policy)
    m_isGetKeyDefined = false;
    auto_fill_type_object(false);
    auto_fill_type_information(false);
  }

  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override {
    const auto& s = *static_cast<RawCdrSample*>(data);
    const auto n = static_cast<std::uint32_t>(s.cdr.size());
    if (n < 4) return false;
    if (payload->max_size < n) payload->reserve(n);
    std::memcpy(payload->data, s.cdr.data(), n);
    payload->length = n;
    // The header's second byte: 0x00 big-endian CDR, 0x01 little-endian (0x02/0x03: PL_CDR).
    payload->encapsulation = (s.cdr[1] & 1) != 0 ? CDR_LE : CDR_BE;
    return true;
  }

  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    auto& s = *static_cast<RawCdrSample*>(data);
    s.cdr.assign(payload->data, payload->data + payload->length);
    return payload->length >= 4;
  }

  std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override {
    const auto n = static_cast<std::uint32_t>(static_cast<RawCdrSample*>(data)->cdr.size());
    return [n]() { return n; };
  }

  void* createData() override { return new RawCdrSample(); }
  void deleteData(void* data) override { delete static_cast<RawCdrSample*>(data); }

  bool getKey(void*, eprosima::fastrtps::rtps::InstanceHandle_t*, bool) override { return false; }
};

}  // namespace vdtnav::ros2
