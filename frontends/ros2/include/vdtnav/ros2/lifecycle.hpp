#pragma once
/// \file
/// \brief A managed node's lifecycle (ROS 2 design article "Managed nodes"; rcl_lifecycle's
/// default state machine), as nav2's lifecycle manager drives it through `<node>/change_state`
/// and reads it through `<node>/get_state`. Primary states unconfigured, inactive, active,
/// finalized; the transitions
///   configure  unconfigured -> inactive      cleanup     inactive -> unconfigured
///   activate   inactive -> active            deactivate  active -> inactive
///   shutdown   unconfigured | inactive | active -> finalized
/// each running its hook; a hook that fails leaves the node where it was (rcl: the transition
/// returns FAILURE) and the call reports success false, as does a transition the state does not
/// have. A transition is named by its id (lifecycle_msgs/msg/Transition) or, with id 0, by its
/// label ("configure", ..., "shutdown"), as rclcpp's change_state service accepts it.

#include <cstdint>
#include <functional>
#include <string>

#include "vdtnav/ros/messages.hpp"

namespace vdtnav::ros2 {

class Lifecycle {
 public:
  /// What the node does on each transition; true: done (an empty hook always succeeds).
  struct Hooks {
    std::function<bool()> configure, activate, deactivate, cleanup, shutdown;
  };
  explicit Lifecycle(Hooks hooks) : hooks_(std::move(hooks)) {}

  /// \return the primary state (lifecycle_msgs/msg/State ids 1..4).
  [[nodiscard]] std::uint8_t state() const noexcept { return state_; }
  [[nodiscard]] ros::LifecycleStateMsg state_msg() const;
  /// \return "unconfigured", "inactive", "active", "finalized" (else "unknown").
  [[nodiscard]] static const char* label(std::uint8_t state);

  struct Result {
    bool success = false;
    ros::TransitionEventMsg event;  ///< what a node publishes on transition_event (success only)
  };
  /// \brief Runs the transition `id` (0: the one labelled `label`); `now_ns` stamps its event.
  Result change(std::uint8_t id, const std::string& label, std::uint64_t now_ns);

 private:
  Hooks hooks_;
  std::uint8_t state_ = 1;  // unconfigured
};

}  // namespace vdtnav::ros2
