// A managed node's lifecycle (lifecycle.hpp): rcl_lifecycle's default state machine.
#include "vdtnav/ros2/lifecycle.hpp"

#include "vdtnav/ros/lifecycle_ids.hpp"

#include <utility>

namespace vdtnav::ros2 {
namespace {

using namespace ros::lifecycle;  // lifecycle_msgs' State and Transition ids
constexpr std::uint8_t kUnconfigured = kPrimaryStateUnconfigured, kInactive = kPrimaryStateInactive,
                       kActive = kPrimaryStateActive, kFinalized = kPrimaryStateFinalized;

struct Edge {
  std::uint8_t from, id, to;
  const char* label;
  std::function<bool()> Lifecycle::Hooks::*hook;
};

constexpr int kEdges = 7;
const Edge* edges() {
  static const Edge e[kEdges] = {
      {kUnconfigured, kTransitionConfigure, kInactive, "configure", &Lifecycle::Hooks::configure},
      {kInactive, kTransitionCleanup, kUnconfigured, "cleanup", &Lifecycle::Hooks::cleanup},
      {kInactive, kTransitionActivate, kActive, "activate", &Lifecycle::Hooks::activate},
      {kActive, kTransitionDeactivate, kInactive, "deactivate", &Lifecycle::Hooks::deactivate},
      {kUnconfigured, kTransitionUnconfiguredShutdown, kFinalized, "shutdown",
       &Lifecycle::Hooks::shutdown},
      {kInactive, kTransitionInactiveShutdown, kFinalized, "shutdown", &Lifecycle::Hooks::shutdown},
      {kActive, kTransitionActiveShutdown, kFinalized, "shutdown", &Lifecycle::Hooks::shutdown},
  };
  return e;
}

}  // namespace

const char* Lifecycle::label(std::uint8_t state) {
  switch (state) {
    case kUnconfigured:
      return "unconfigured";
    case kInactive:
      return "inactive";
    case kActive:
      return "active";
    case kFinalized:
      return "finalized";
    default:
      return "unknown";
  }
}

ros::LifecycleStateMsg Lifecycle::state_msg() const {
  ros::LifecycleStateMsg s;
  s.id = state_;
  s.label = label(state_);
  return s;
}

Lifecycle::Result Lifecycle::change(std::uint8_t id, const std::string& name,
                                    std::uint64_t now_ns) {
  Result r;
  for (int k = 0; k < kEdges; ++k) {
    const Edge& e = edges()[k];
    if (e.from != state_ || (id != 0 ? e.id != id : name != e.label)) continue;
    const std::function<bool()>& hook = hooks_.*(e.hook);
    if (hook && !hook()) return r;  // stays where it was
    r.success = true;
    r.event.timestamp = now_ns;
    r.event.transition.id = e.id;
    r.event.transition.label = e.label;
    r.event.start_state = state_msg();
    state_ = e.to;
    r.event.goal_state = state_msg();
    return r;
  }
  return r;
}

}  // namespace vdtnav::ros2
