#pragma once
/// \file
/// \brief The ids of a ROS 2 managed (lifecycle) node's states and transitions: the constants of
/// lifecycle_msgs/msg/State.msg and lifecycle_msgs/msg/Transition.msg (rcl_interfaces, the same
/// in Humble and Jazzy), as LifecycleStateMsg::id and LifecycleTransitionMsg::id carry them
/// (messages.hpp). Each is named for its ROS constant in kCamelCase: kPrimaryStateActive is
/// PRIMARY_STATE_ACTIVE, kTransitionOnConfigureSuccess TRANSITION_ON_CONFIGURE_SUCCESS,
/// kTransitionStateCleaningUp TRANSITION_STATE_CLEANINGUP.

#include <cstdint>

namespace vdtnav::ros::lifecycle {

// ---- lifecycle_msgs/msg/State
// The primary states (and unknown) ...
inline constexpr std::uint8_t kPrimaryStateUnknown = 0;
inline constexpr std::uint8_t kPrimaryStateUnconfigured = 1;
inline constexpr std::uint8_t kPrimaryStateInactive = 2;
inline constexpr std::uint8_t kPrimaryStateActive = 3;
inline constexpr std::uint8_t kPrimaryStateFinalized = 4;
// ... and the intermediate states, in which a transition's callback runs.
inline constexpr std::uint8_t kTransitionStateConfiguring = 10;
inline constexpr std::uint8_t kTransitionStateCleaningUp = 11;
inline constexpr std::uint8_t kTransitionStateShuttingDown = 12;
inline constexpr std::uint8_t kTransitionStateActivating = 13;
inline constexpr std::uint8_t kTransitionStateDeactivating = 14;
inline constexpr std::uint8_t kTransitionStateErrorProcessing = 15;

// ---- lifecycle_msgs/msg/Transition
// [0, 9] the public transitions, the ones a ChangeState request asks for ...
inline constexpr std::uint8_t kTransitionCreate = 0;
inline constexpr std::uint8_t kTransitionConfigure = 1;
inline constexpr std::uint8_t kTransitionCleanup = 2;
inline constexpr std::uint8_t kTransitionActivate = 3;
inline constexpr std::uint8_t kTransitionDeactivate = 4;
inline constexpr std::uint8_t kTransitionUnconfiguredShutdown = 5;
inline constexpr std::uint8_t kTransitionInactiveShutdown = 6;
inline constexpr std::uint8_t kTransitionActiveShutdown = 7;
inline constexpr std::uint8_t kTransitionDestroy = 8;
// ... [10, 69] the private ones, taken on a callback's result (success, failure, error) ...
inline constexpr std::uint8_t kTransitionOnConfigureSuccess = 10;
inline constexpr std::uint8_t kTransitionOnConfigureFailure = 11;
inline constexpr std::uint8_t kTransitionOnConfigureError = 12;
inline constexpr std::uint8_t kTransitionOnCleanupSuccess = 20;
inline constexpr std::uint8_t kTransitionOnCleanupFailure = 21;
inline constexpr std::uint8_t kTransitionOnCleanupError = 22;
inline constexpr std::uint8_t kTransitionOnActivateSuccess = 30;
inline constexpr std::uint8_t kTransitionOnActivateFailure = 31;
inline constexpr std::uint8_t kTransitionOnActivateError = 32;
inline constexpr std::uint8_t kTransitionOnDeactivateSuccess = 40;
inline constexpr std::uint8_t kTransitionOnDeactivateFailure = 41;
inline constexpr std::uint8_t kTransitionOnDeactivateError = 42;
inline constexpr std::uint8_t kTransitionOnShutdownSuccess = 50;
inline constexpr std::uint8_t kTransitionOnShutdownFailure = 51;
inline constexpr std::uint8_t kTransitionOnShutdownError = 52;
inline constexpr std::uint8_t kTransitionOnErrorSuccess = 60;
inline constexpr std::uint8_t kTransitionOnErrorFailure = 61;
inline constexpr std::uint8_t kTransitionOnErrorError = 62;
// ... and [90, 99] the results a transition's callback returns (not transitions themselves).
inline constexpr std::uint8_t kTransitionCallbackSuccess = 97;
inline constexpr std::uint8_t kTransitionCallbackFailure = 98;
inline constexpr std::uint8_t kTransitionCallbackError = 99;

}  // namespace vdtnav::ros::lifecycle
