#pragma once
/// \file
/// \brief ROS 2 services over DDS as ROS 2's default middleware (rmw_fastrtps) carries them: a
/// service `/name` of type `pkg/srv/Type` is a request topic `rq/nameRequest`
/// (`pkg::srv::dds_::Type_Request_`) and a reply topic `rr/nameReply` (`..._Response_`), both
/// reliable, volatile, keep last 10 (rmw_qos_profile_services_default). A client writes its
/// request with the GUID of its reply reader as the related sample identity; the server answers
/// with the related sample identity (that GUID, the request's sequence number), so that each
/// client takes its own replies. This identity travels in DDS's inline QoS, which is why a
/// client and a server of different DDS vendors do not understand each other (Cyclone's rmw puts
/// it in the payload instead): services need the same vendor.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "vdtnav/ros2/dds.hpp"

namespace vdtnav::ros2 {

/// \brief A request as taken: its bytes and the identity the reply must carry.
struct Request {
  std::vector<std::uint8_t> cdr;
  SampleIdentity reply_to;
};

/// \brief A service server. Requests are handed to `on_request` on a DDS thread; answer them with
/// reply() from any thread, in any order.
class ServiceServer {
 public:
  /// \param name the resolved ROS name ("/amcl/change_state"); \param type "pkg/srv/Type".
  ServiceServer(Participant& participant, const std::string& name, const std::string& type,
                std::function<void(const Request&)> on_request);
  /// \brief Sends `response` (CDR) to the client of `request`; waits up to 1 s for the client's
  /// reply reader to be matched (a reply before that would be lost, as rmw_fastrtps knows).
  bool reply(const Request& request, const std::vector<std::uint8_t>& response);
  /// \brief Waits up to `seconds` until every reply sent was acknowledged (before the process
  /// ends: a reply still in flight dies with it).
  bool flush(double seconds);
  [[nodiscard]] const std::string& name() const noexcept { return name_; }

 private:
  std::string name_;
  std::unique_ptr<Writer> replies_;
  std::unique_ptr<Reader> requests_;
};

/// \brief A service client, built the way rmw_fastrtps builds one (what nav2's lifecycle manager
/// and `ros2 service call` use over Fast DDS).
class ServiceClient {
 public:
  ServiceClient(Participant& participant, const std::string& name, const std::string& type);
  /// \return whether a server is matched (its request reader and reply writer).
  [[nodiscard]] bool ready() const;
  /// \brief Waits up to `timeout` for ready().
  bool wait_ready(std::chrono::duration<double> timeout) const;
  /// \brief Sends `request` (CDR) and waits up to `timeout` for its reply (none: nullopt).
  std::optional<std::vector<std::uint8_t>> call(const std::vector<std::uint8_t>& request,
                                                std::chrono::duration<double> timeout);

 private:
  std::unique_ptr<Writer> requests_;
  std::unique_ptr<Reader> replies_;
  SampleIdentity reader_guid_;
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::map<std::int64_t, std::vector<std::uint8_t>> replies_by_sequence_;
};

/// \brief The DDS topic names of a service: {"rq/nameRequest", "rr/nameReply"}.
[[nodiscard]] std::pair<std::string, std::string> service_topics(const std::string& name);

}  // namespace vdtnav::ros2
