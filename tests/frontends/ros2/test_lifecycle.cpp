// A managed node's lifecycle (lifecycle.hpp) against rcl_lifecycle's default state machine
// (ROS 2 design article "Managed nodes"): every primary state and transition id, by id and by
// label, a failing hook, and transitions a state does not have.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "vdtnav/ros2/lifecycle.hpp"

namespace {

using vdtnav::ros2::Lifecycle;

TEST(Lifecycle, FollowsRclsDefaultStateMachine) {
  std::vector<std::string> ran;
  Lifecycle lc({[&] { return ran.push_back("configure"), true; },
                [&] { return ran.push_back("activate"), true; },
                [&] { return ran.push_back("deactivate"), true; },
                [&] { return ran.push_back("cleanup"), true; },
                [&] { return ran.push_back("shutdown"), true; }});
  EXPECT_EQ(lc.state(), 1);  // unconfigured
  EXPECT_STREQ(Lifecycle::label(lc.state()), "unconfigured");
  // Not from unconfigured: activate (3), deactivate (4), cleanup (2), inactive shutdown (6).
  for (std::uint8_t id : {3, 4, 2, 6, 7}) EXPECT_FALSE(lc.change(id, "", 0).success) << int(id);
  EXPECT_TRUE(ran.empty());
  const Lifecycle::Result c = lc.change(1, "", 42);  // configure
  ASSERT_TRUE(c.success);
  EXPECT_EQ(lc.state(), 2);
  EXPECT_EQ(c.event.timestamp, 42U);
  EXPECT_EQ(c.event.transition.id, 1);
  EXPECT_EQ(c.event.transition.label, "configure");
  EXPECT_EQ(c.event.start_state.id, 1);
  EXPECT_EQ(c.event.start_state.label, "unconfigured");
  EXPECT_EQ(c.event.goal_state.id, 2);
  EXPECT_EQ(c.event.goal_state.label, "inactive");
  EXPECT_TRUE(lc.change(0, "activate", 0).success);  // by label, as rclcpp accepts it
  EXPECT_EQ(lc.state(), 3);
  EXPECT_FALSE(lc.change(1, "", 0).success);  // configure from active
  EXPECT_TRUE(lc.change(4, "", 0).success);   // deactivate
  EXPECT_EQ(lc.state(), 2);
  EXPECT_TRUE(lc.change(3, "", 0).success);  // activate again
  EXPECT_TRUE(lc.change(4, "", 0).success);
  EXPECT_TRUE(lc.change(2, "", 0).success);  // cleanup
  EXPECT_EQ(lc.state(), 1);
  EXPECT_TRUE(lc.change(0, "shutdown", 0).success);  // unconfigured shutdown (5)
  EXPECT_EQ(lc.state(), 4);
  EXPECT_STREQ(Lifecycle::label(lc.state()), "finalized");
  EXPECT_FALSE(lc.change(1, "", 0).success);  // nothing leaves finalized
  EXPECT_EQ(ran, (std::vector<std::string>{"configure", "activate", "deactivate", "activate",
                                           "deactivate", "cleanup", "shutdown"}));
}

TEST(Lifecycle, AFailingHookLeavesTheNodeWhereItWas) {
  bool map_there = false;
  Lifecycle lc({[&] { return map_there; }, {}, {}, {}, {}});
  EXPECT_FALSE(lc.change(1, "", 0).success);
  EXPECT_EQ(lc.state(), 1);
  map_there = true;
  EXPECT_TRUE(lc.change(1, "", 0).success);
  EXPECT_EQ(lc.state(), 2);
  EXPECT_TRUE(lc.change(6, "", 0).success);  // inactive shutdown
  EXPECT_EQ(lc.state(), 4);
}

}  // namespace
