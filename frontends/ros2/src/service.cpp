// ROS 2 services over DDS, rmw_fastrtps's way (service.hpp).
#include "vdtnav/ros2/service.hpp"

#include <thread>
#include <utility>

namespace vdtnav::ros2 {
namespace {

/// rmw_qos_profile_services_default.
Qos services_qos() { return Qos{Qos::Reliability::kReliable, Qos::Durability::kVolatile, 10}; }

}  // namespace

std::pair<std::string, std::string> service_topics(const std::string& name) {
  const std::string topic = dds_topic_name(name).substr(3);  // "amcl/change_state"
  return {"rq/" + topic + "Request", "rr/" + topic + "Reply"};
}

ServiceServer::ServiceServer(Participant& participant, const std::string& name,
                             const std::string& type,
                             std::function<void(const Request&)> on_request)
    : name_(name) {
  const auto [rq, rr] = service_topics(name);
  replies_ = participant.dds_writer(rr, type + "_Response", services_qos());
  requests_ = participant.dds_reader(rq, type + "_Request", services_qos(),
                                     [on_request = std::move(on_request)](const Sample& s) {
                                       Request r;
                                       r.cdr = s.cdr;
                                       // The request's identity, with the client's reply reader as
                                       // its GUID when it says which.
                                       r.reply_to = s.identity;
                                       if (s.related.known()) r.reply_to.guid = s.related.guid;
                                       on_request(r);
                                     });
}

bool ServiceServer::reply(const Request& request, const std::vector<std::uint8_t>& response) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  while (replies_->matched() == 0 && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return replies_->write(response, request.reply_to, nullptr);
}

bool ServiceServer::flush(double seconds) { return replies_->wait_acknowledged(seconds); }

ServiceClient::ServiceClient(Participant& participant, const std::string& name,
                             const std::string& type) {
  const auto [rq, rr] = service_topics(name);
  replies_ =
      participant.dds_reader(rr, type + "_Response", services_qos(), [this](const Sample& s) {
        if (s.related.guid != reader_guid_.guid) return;  // another client's
        std::lock_guard<std::mutex> lock(mutex_);
        replies_by_sequence_[s.related.sequence] = s.cdr;
        arrived_.notify_all();
      });
  reader_guid_ = replies_->guid();
  requests_ = participant.dds_writer(rq, type + "_Request", services_qos());
}

bool ServiceClient::ready() const { return requests_->matched() > 0 && replies_->matched() > 0; }

bool ServiceClient::wait_ready(std::chrono::duration<double> timeout) const {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (!ready()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

std::optional<std::vector<std::uint8_t>> ServiceClient::call(
    const std::vector<std::uint8_t>& request, std::chrono::duration<double> timeout) {
  SampleIdentity related = reader_guid_;
  related.sequence = 0;
  SampleIdentity written;
  if (!requests_->write(request, related, &written)) return std::nullopt;
  std::unique_lock<std::mutex> lock(mutex_);
  if (!arrived_.wait_for(lock, timeout,
                         [&] { return replies_by_sequence_.count(written.sequence); }))
    return std::nullopt;
  std::vector<std::uint8_t> out = std::move(replies_by_sequence_[written.sequence]);
  replies_by_sequence_.erase(written.sequence);
  return out;
}

}  // namespace vdtnav::ros2
