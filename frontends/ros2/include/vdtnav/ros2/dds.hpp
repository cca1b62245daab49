#pragma once
/// \file
/// \brief A ROS 2 graph participant without rclcpp: eProsima Fast DDS (the DDS of ROS 2's
/// default middleware, rmw_fastrtps_cpp) with ROS 2's mapping onto DDS (the ROS 2 design article
/// "Topic and Service name mapping to DDS"):
/// - a topic `/name` (or `name`, relative to the root namespace) is the DDS topic `rt/name`;
///   a service's request and reply topics are `rq/nameRequest` and `rr/nameReply`;
/// - a message type `pkg/msg/Type` is the DDS type `pkg::msg::dds_::Type_`;
/// - samples are plain CDR (XCDR1) with their 4-byte encapsulation header, exactly the bytes
///   rmw writes into a rosbag2 (messages.hpp's structs go through cdr_writer.hpp and the bag
///   decoders: this layer moves bytes and never parses them).
/// No Fast DDS type crosses this header.
///
/// Where a participant talks (network.md): ROS 2's own switches, read from the environment as
/// rmw reads them: ROS_DOMAIN_ID (default 0), and ROS_LOCALHOST_ONLY=1 or
/// ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST (or ParticipantOptions::loopback) confine it to the
/// loopback interface: UDP on 127.0.0.1 only, discovery by unicast to the well-known ports of
/// the participants 0..kLoopbackPeers on 127.0.0.1, no multicast, no shared memory. Otherwise
/// Fast DDS's defaults (multicast discovery on every interface), what a ROS 2 node does.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace vdtnav::ros2 {

/// \brief The DDS topic of a ROS topic name: "/amcl_pose" or "amcl_pose" -> "rt/amcl_pose".
/// \throws ConfigError for an empty name or one ending in '/'.
[[nodiscard]] std::string dds_topic_name(const std::string& ros_topic);
/// \brief The DDS type of a ROS 2 type: "geometry_msgs/msg/PoseWithCovarianceStamped" ->
/// "geometry_msgs::msg::dds_::PoseWithCovarianceStamped_" (also for srv types' Request and
/// Response: "lifecycle_msgs/srv/ChangeState_Request" -> "lifecycle_msgs::srv::dds_::
/// ChangeState_Request_").
/// \throws ConfigError unless the name has the form pkg/msg/Type or pkg/srv/Type.
[[nodiscard]] std::string dds_type_name(const std::string& ros_type);

/// \brief The QoS of a topic, in ROS 2's terms (rmw_qos_profile_t's history, depth,
/// reliability and durability; deadline, lifespan and liveliness at their defaults).
struct Qos {
  enum class Reliability { kReliable, kBestEffort };
  enum class Durability { kVolatile, kTransientLocal };
  Reliability reliability = Reliability::kReliable;
  Durability durability = Durability::kVolatile;
  int depth = 10;  ///< keep last this many

  /// rclcpp::SystemDefaultsQoS / rmw_qos_profile_default: reliable, volatile, keep last 10.
  [[nodiscard]] static Qos defaults() { return {}; }
  /// rclcpp::SensorDataQoS (what nav2's amcl subscribes `scan` with): best effort, volatile,
  /// keep last 5.
  [[nodiscard]] static Qos sensor_data() {
    return {Reliability::kBestEffort, Durability::kVolatile, 5};
  }
  /// Latched topics (nav2's `map`, amcl's `amcl_pose`, tf2's `/tf_static`): reliable, transient
  /// local, keep last `depth`.
  [[nodiscard]] static Qos transient_local(int depth = 1) {
    return {Reliability::kReliable, Durability::kTransientLocal, depth};
  }
};

/// \brief A sample's identity (RTPS's SampleIdentity): the GUID of the writer (or, for a
/// service, of the endpoint a reply is for) and a sequence number.
struct SampleIdentity {
  std::array<std::uint8_t, 16> guid{};  ///< 12-byte prefix, 4-byte entity id; all 0: unknown
  std::int64_t sequence = 0;
  [[nodiscard]] bool known() const noexcept {
    for (std::uint8_t b : guid) {
      if (b != 0) return true;
    }
    return false;
  }
  bool operator==(const SampleIdentity& o) const noexcept {
    return guid == o.guid && sequence == o.sequence;
  }
};

/// \brief One sample as received.
struct Sample {
  std::vector<std::uint8_t> cdr;  ///< CDR with its encapsulation header
  std::int64_t source_ns = 0;     ///< the writer's source timestamp
  SampleIdentity identity;        ///< this sample's (writer GUID, sequence number)
  SampleIdentity related;         ///< the related sample's, as the writer gave it (services)
};

/// \brief The participant's domain and network.
struct ParticipantOptions {
  /// DDS domain id; < 0: ROS_DOMAIN_ID, or 0 when it is unset.
  int domain = -1;
  /// Confine to 127.0.0.1 (see the file comment); unset: from the environment.
  enum class Network { kFromEnvironment, kLoopback, kDefault };
  Network network = Network::kFromEnvironment;
  /// The participant's name (what DDS tools show).
  std::string name = "vdtnav";
};

/// Participants whose well-known unicast ports a loopback participant sends its discovery to
/// (participant ids 0..kLoopbackPeers-1 on 127.0.0.1: the processes of one machine).
inline constexpr int kLoopbackPeers = 32;

/// \brief A writer of one topic (raw CDR samples).
class Writer {
 public:
  virtual ~Writer() = default;
  /// \brief Publishes one sample (CDR with its encapsulation header, at least 4 bytes).
  /// \return false when DDS refused it (a full history of a reliable writer, ...).
  virtual bool write(const std::vector<std::uint8_t>& cdr) = 0;
  /// \brief Publishes one sample with a related sample identity (DDS's WriteParams, what ROS 2's
  /// default middleware uses for services); `*written` receives this sample's own identity.
  virtual bool write(const std::vector<std::uint8_t>& cdr, const SampleIdentity& related,
                     SampleIdentity* written) = 0;
  /// \return the readers matched now.
  [[nodiscard]] virtual int matched() const = 0;
  /// \brief Waits up to `seconds` until the matched reliable readers acknowledged every sample.
  /// \return false on timeout.
  virtual bool wait_acknowledged(double seconds) = 0;
};

/// \brief A reader of one topic; its callback runs on a DDS thread, one sample at a time.
class Reader {
 public:
  virtual ~Reader() = default;
  /// \return the writers matched now.
  [[nodiscard]] virtual int matched() const = 0;
  /// \return this reader's GUID.
  [[nodiscard]] virtual SampleIdentity guid() const = 0;
};

/// \brief A DDS domain participant with ROS 2's naming (see the file comment).
class Participant {
 public:
  /// \throws Error when Fast DDS cannot create the participant (the domain id out of range, no
  /// port free).
  explicit Participant(ParticipantOptions options = {});
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  /// \brief A writer of the ROS topic `topic` with ROS 2 type `type` ("sensor_msgs/msg/LaserScan").
  [[nodiscard]] std::unique_ptr<Writer> writer(const std::string& topic, const std::string& type,
                                               const Qos& qos);
  /// \brief A reader of `topic`; `on_sample` is called for every sample with data.
  [[nodiscard]] std::unique_ptr<Reader> reader(const std::string& topic, const std::string& type,
                                               const Qos& qos,
                                               std::function<void(const Sample&)> on_sample);
  /// \brief The same on a DDS topic name as is (`rq/...Request`, `ros_discovery_info` is
  /// `rt/ros_discovery_info`): what writer() and reader() use after dds_topic_name().
  [[nodiscard]] std::unique_ptr<Writer> dds_writer(const std::string& dds_topic,
                                                   const std::string& ros_type, const Qos& qos);
  [[nodiscard]] std::unique_ptr<Reader> dds_reader(const std::string& dds_topic,
                                                   const std::string& ros_type, const Qos& qos,
                                                   std::function<void(const Sample&)> on_sample);

  [[nodiscard]] int domain() const noexcept { return domain_; }
  [[nodiscard]] bool loopback() const noexcept { return loopback_; }
  /// \return the participant's GUID prefix (12 bytes), the first bytes of every entity's GID.
  [[nodiscard]] std::vector<std::uint8_t> guid_prefix() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  int domain_ = 0;
  bool loopback_ = false;
};

}  // namespace vdtnav::ros2
