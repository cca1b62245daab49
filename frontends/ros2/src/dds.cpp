// The ROS 2 participant on Fast DDS 2.9 (dds.hpp): one DomainParticipant, one publisher and one
// subscriber, a topic per name, and the raw CDR type (raw_cdr_type.hpp) for every ROS type.
#include "vdtnav/ros2/dds.hpp"

#include <fastdds/rtps/common/SampleIdentity.h>
#include <fastdds/rtps/common/WriteParams.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string>
#include <utility>

#include "raw_cdr_type.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::ros2 {

namespace dds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;

std::string dds_topic_name(const std::string& ros_topic) {
  std::string name = ros_topic;
  if (!name.empty() && name.front() == '/') name.erase(0, 1);
  if (name.empty() || name.back() == '/') {
    throw ConfigError("a ROS topic name: expected /name or name, got '" + ros_topic + "'");
  }
  return "rt/" + name;
}

std::string dds_type_name(const std::string& ros_type) {
  const std::size_t a = ros_type.find('/');
  const std::size_t b = a == std::string::npos ? a : ros_type.find('/', a + 1);
  const std::string kind = b == std::string::npos ? "" : ros_type.substr(a + 1, b - a - 1);
  if (a == 0 || b == std::string::npos || b + 1 >= ros_type.size() ||
      ros_type.find('/', b + 1) != std::string::npos || (kind != "msg" && kind != "srv")) {
    throw ConfigError("a ROS 2 type: expected pkg/msg/Type or pkg/srv/Type, got '" + ros_type +
                      "'");
  }
  return ros_type.substr(0, a) + "::" + kind + "::dds_::" + ros_type.substr(b + 1) + "_";
}

namespace {

bool env_is(const char* name, const char* value) {
  const char* v = std::getenv(name);
  return v != nullptr && std::string(v) == value;
}

int domain_from(int asked) {
  if (asked >= 0) return asked;
  const char* v = std::getenv("ROS_DOMAIN_ID");
  if (v == nullptr || *v == '\0') return 0;
  char* end = nullptr;
  const long d = std::strtol(v, &end, 10);
  if (*end != '\0' || d < 0 || d > 232) {
    throw ConfigError(std::string("ROS_DOMAIN_ID: expected a domain id 0..232, got '") + v + "'");
  }
  return static_cast<int>(d);
}

rtps::Locator_t loopback_locator() {
  rtps::Locator_t l;
  l.kind = LOCATOR_KIND_UDPv4;
  rtps::IPLocator::setIPv4(l, 127, 0, 0, 1);
  l.port = 0;  // Fast DDS puts the well-known port of this participant (or, for a peer, of each)
  return l;
}

/// The participant's QoS: on the loopback interface only (see dds.hpp), or Fast DDS's default.
dds::DomainParticipantQos participant_qos(const std::string& name, bool loopback) {
  dds::DomainParticipantQos q = dds::PARTICIPANT_QOS_DEFAULT;
  q.name(name);
  if (!loopback) return q;
  q.transport().use_builtin_transports = false;  // no shared memory, no other interface
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.emplace_back("127.0.0.1");
  udp->maxInitialPeersRange = kLoopbackPeers;
  q.transport().user_transports.push_back(udp);
  auto& builtin = q.wire_protocol().builtin;
  builtin.initialPeersList.clear();
  builtin.initialPeersList.push_back(loopback_locator());
  // Unicast locators given: Fast DDS adds no multicast one (its default when both are empty).
  builtin.metatrafficMulticastLocatorList.clear();
  builtin.metatrafficUnicastLocatorList.clear();
  builtin.metatrafficUnicastLocatorList.push_back(loopback_locator());
  builtin.avoid_builtin_multicast = true;
  q.wire_protocol().default_multicast_locator_list.clear();
  q.wire_protocol().default_unicast_locator_list.clear();
  q.wire_protocol().default_unicast_locator_list.push_back(loopback_locator());
  return q;
}

void apply(const Qos& qos, dds::ReliabilityQosPolicy& r, dds::DurabilityQosPolicy& d,
           dds::HistoryQosPolicy& h) {
  r.kind = qos.reliability == Qos::Reliability::kReliable ? dds::RELIABLE_RELIABILITY_QOS
                                                          : dds::BEST_EFFORT_RELIABILITY_QOS;
  d.kind = qos.durability == Qos::Durability::kTransientLocal ? dds::TRANSIENT_LOCAL_DURABILITY_QOS
                                                              : dds::VOLATILE_DURABILITY_QOS;
  h.kind = dds::KEEP_LAST_HISTORY_QOS;
  h.depth = qos.depth;
}

}  // namespace

struct Participant::Impl {
  dds::DomainParticipant* participant = nullptr;
  dds::Publisher* publisher = nullptr;
  dds::Subscriber* subscriber = nullptr;
  std::mutex mutex;                               // topics: shared by writers and readers
  std::map<std::string, dds::Topic*> topics;      // by DDS topic name
  std::map<std::string, dds::TypeSupport> types;  // by DDS type name

  dds::Topic* topic(const std::string& dds_topic, const std::string& ros_type) {
    const std::string type = dds_type_name(ros_type);
    std::lock_guard<std::mutex> lock(mutex);
    if (types.count(type) == 0) {
      dds::TypeSupport support(new RawCdrType(type));
      if (support.register_type(participant) != ReturnCode_t::RETCODE_OK) {
        throw Error("Fast DDS: cannot register the type " + type);
      }
      types.emplace(type, support);
    }
    const auto it = topics.find(dds_topic);
    if (it != topics.end()) {
      if (it->second->get_type_name() != type) {
        throw ConfigError("the DDS topic " + dds_topic + " has type " +
                          it->second->get_type_name() + ", asked for " + type);
      }
      return it->second;
    }
    dds::Topic* t = participant->create_topic(dds_topic, type, dds::TOPIC_QOS_DEFAULT);
    if (t == nullptr) throw Error("Fast DDS: cannot create the topic " + dds_topic);
    topics.emplace(dds_topic, t);
    return t;
  }
};

namespace {

SampleIdentity from_rtps(const rtps::SampleIdentity& id) {
  SampleIdentity out;
  const rtps::GUID_t& g = id.writer_guid();
  std::copy(g.guidPrefix.value, g.guidPrefix.value + rtps::GuidPrefix_t::size, out.guid.begin());
  std::copy(g.entityId.value, g.entityId.value + rtps::EntityId_t::size,
            out.guid.begin() + rtps::GuidPrefix_t::size);
  out.sequence = static_cast<std::int64_t>(id.sequence_number().to64long());
  return out;
}

rtps::SampleIdentity to_rtps(const SampleIdentity& id) {
  rtps::SampleIdentity out;
  if (!id.known()) return rtps::SampleIdentity::unknown();
  rtps::GUID_t& g = out.writer_guid();
  std::copy(id.guid.begin(), id.guid.begin() + rtps::GuidPrefix_t::size, g.guidPrefix.value);
  std::copy(id.guid.begin() + rtps::GuidPrefix_t::size, id.guid.end(), g.entityId.value);
  out.sequence_number() = rtps::SequenceNumber_t(static_cast<std::uint64_t>(id.sequence));
  return out;
}

class DdsWriter final : public Writer {
 public:
  DdsWriter(dds::Publisher* publisher, dds::DataWriter* writer)
      : publisher_(publisher), writer_(writer) {}
  ~DdsWriter() override { publisher_->delete_datawriter(writer_); }
  bool write(const std::vector<std::uint8_t>& cdr) override {
    if (cdr.size() < 4) return false;
    RawCdrSample s{cdr};
    return writer_->write(&s);
  }
  bool write(const std::vector<std::uint8_t>& cdr, const SampleIdentity& related,
             SampleIdentity* written) override {
    if (cdr.size() < 4) return false;
    RawCdrSample s{cdr};
    rtps::WriteParams params;
    params.related_sample_identity(to_rtps(related));
    if (!writer_->write(&s, params)) return false;
    if (written != nullptr) *written = from_rtps(params.sample_identity());
    return true;
  }
  bool wait_acknowledged(double seconds) override {
    eprosima::fastrtps::Duration_t d(seconds);
    return writer_->wait_for_acknowledgments(d) == ReturnCode_t::RETCODE_OK;
  }
  [[nodiscard]] int matched() const override {
    dds::PublicationMatchedStatus status;
    writer_->get_publication_matched_status(status);
    return status.current_count;
  }

 private:
  dds::Publisher* publisher_;
  dds::DataWriter* writer_;
};

class DdsReader final : public Reader, public dds::DataReaderListener {
 public:
  DdsReader(dds::Subscriber* subscriber, std::function<void(const Sample&)> on_sample)
      : subscriber_(subscriber), on_sample_(std::move(on_sample)) {}
  ~DdsReader() override {
    if (reader_ != nullptr) {
      reader_->set_listener(nullptr);
      subscriber_->delete_datareader(reader_);
    }
  }
  void attach(dds::DataReader* reader) { reader_ = reader; }
  [[nodiscard]] int matched() const override {
    dds::SubscriptionMatchedStatus status;
    reader_->get_subscription_matched_status(status);
    return status.current_count;
  }
  [[nodiscard]] SampleIdentity guid() const override {
    rtps::SampleIdentity id;
    id.writer_guid(reader_->guid());
    id.sequence_number(rtps::SequenceNumber_t());
    return from_rtps(id);
  }
  void on_data_available(dds::DataReader* reader) override {
    RawCdrSample s;
    dds::SampleInfo info;
    while (reader->take_next_sample(&s, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      Sample out;
      out.cdr = std::move(s.cdr);
      out.source_ns = static_cast<std::int64_t>(info.source_timestamp.to_ns());
      out.identity = from_rtps(info.sample_identity);
      out.related = from_rtps(info.related_sample_identity);
      on_sample_(out);
      s.cdr.clear();
    }
  }

 private:
  dds::Subscriber* subscriber_;
  dds::DataReader* reader_ = nullptr;
  std::function<void(const Sample&)> on_sample_;
};

}  // namespace

Participant::Participant(ParticipantOptions options) : impl_(std::make_unique<Impl>()) {
  domain_ = domain_from(options.domain);
  switch (options.network) {
    case ParticipantOptions::Network::kLoopback:
      loopback_ = true;
      break;
    case ParticipantOptions::Network::kDefault:
      loopback_ = false;
      break;
    case ParticipantOptions::Network::kFromEnvironment:
      loopback_ =
          env_is("ROS_LOCALHOST_ONLY", "1") || env_is("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST");
      break;
  }
  impl_->participant = dds::DomainParticipantFactory::get_instance()->create_participant(
      static_cast<dds::DomainId_t>(domain_), participant_qos(options.name, loopback_));
  if (impl_->participant == nullptr) {
    throw Error("Fast DDS: cannot create a participant on domain " + std::to_string(domain_));
  }
  impl_->publisher = impl_->participant->create_publisher(dds::PUBLISHER_QOS_DEFAULT);
  impl_->subscriber = impl_->participant->create_subscriber(dds::SUBSCRIBER_QOS_DEFAULT);
  if (impl_->publisher == nullptr || impl_->subscriber == nullptr) {
    throw Error("Fast DDS: cannot create a publisher and a subscriber");
  }
}

Participant::~Participant() {
  if (impl_->participant == nullptr) return;
  // Writers and readers are the caller's and deleted before this (their owners go first).
  impl_->participant->delete_contained_entities();
  dds::DomainParticipantFactory::get_instance()->delete_participant(impl_->participant);
}

std::unique_ptr<Writer> Participant::writer(const std::string& topic, const std::string& type,
                                            const Qos& qos) {
  return dds_writer(dds_topic_name(topic), type, qos);
}

std::unique_ptr<Reader> Participant::reader(const std::string& topic, const std::string& type,
                                            const Qos& qos,
                                            std::function<void(const Sample&)> on_sample) {
  return dds_reader(dds_topic_name(topic), type, qos, std::move(on_sample));
}

std::unique_ptr<Writer> Participant::dds_writer(const std::string& dds_topic,
                                                const std::string& ros_type, const Qos& qos) {
  dds::Topic* t = impl_->topic(dds_topic, ros_type);
  dds::DataWriterQos q = dds::DATAWRITER_QOS_DEFAULT;
  apply(qos, q.reliability(), q.durability(), q.history());
  // As rmw_fastrtps: payloads grow with the message (a map is megabytes), no data sharing.
  q.endpoint().history_memory_policy = rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  q.data_sharing().off();
  // Synchronous: write() sends the sample at once, so that a keep-last-1 writer (amcl_pose) does
  // not replace a sample not yet sent; large samples (a map) are fragmented all the same.
  q.publish_mode().kind = dds::SYNCHRONOUS_PUBLISH_MODE;
  dds::DataWriter* w = impl_->publisher->create_datawriter(t, q);
  if (w == nullptr) throw Error("Fast DDS: cannot create a writer of " + dds_topic);
  return std::make_unique<DdsWriter>(impl_->publisher, w);
}

std::unique_ptr<Reader> Participant::dds_reader(const std::string& dds_topic,
                                                const std::string& ros_type, const Qos& qos,
                                                std::function<void(const Sample&)> on_sample) {
  dds::Topic* t = impl_->topic(dds_topic, ros_type);
  dds::DataReaderQos q = dds::DATAREADER_QOS_DEFAULT;
  apply(qos, q.reliability(), q.durability(), q.history());
  q.endpoint().history_memory_policy = rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  q.data_sharing().off();
  auto reader = std::make_unique<DdsReader>(impl_->subscriber, std::move(on_sample));
  dds::DataReader* r = impl_->subscriber->create_datareader(t, q, reader.get());
  if (r == nullptr) throw Error("Fast DDS: cannot create a reader of " + dds_topic);
  reader->attach(r);
  return reader;
}

std::vector<std::uint8_t> Participant::guid_prefix() const {
  const rtps::GuidPrefix_t& p = impl_->participant->guid().guidPrefix;
  return std::vector<std::uint8_t>(p.value, p.value + rtps::GuidPrefix_t::size);
}

}  // namespace vdtnav::ros2
