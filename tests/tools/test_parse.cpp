// The CLI's text options: poses are three finite numbers with the yaw wrapped; standard
// deviations are three finite non-negative numbers and are never wrapped; a bad text names the
// option, echoes the text and says what was expected.
#include "parse.hpp"

#include <gtest/gtest.h>

#include <string>

#include "vdtnav/core/error.hpp"

namespace vdtnav::tools {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// The message of the ConfigError that `f` throws ("" if it throws none).
template <class F>
std::string config_error(F f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ParsePose, ReadsThreeNumbersAndWrapsTheYaw) {
  EXPECT_TRUE(parse_pose("1.5,-2,0.25", "--init").isApprox(Pose2(1.5, -2.0, 0.25)));
  EXPECT_TRUE(parse_pose(" 1 , 2 ,3 ", "--init").isApprox(Pose2(1.0, 2.0, 3.0)));
  EXPECT_NEAR(parse_pose("0,0,7", "--init")[2], 7.0 - 2.0 * kPi, 1e-12);
  EXPECT_NEAR(parse_pose("0,0,-4", "--init")[2], -4.0 + 2.0 * kPi, 1e-12);
}

TEST(ParsePose, RejectsMalformedTextNamingTheOption) {
  for (const std::string bad :
       {"", "1,2", "1,2,3,4", "1;2;3", "1,,3", "a,2,3", "1,2,3x", "1,2,nan", "1,inf,3", "1,2,3,"}) {
    const std::string msg = config_error([&] { (void)parse_pose(bad, "--init"); });
    EXPECT_NE(msg.find("--init: expected x,y,yaw"), std::string::npos)
        << "'" << bad << "': " << msg;
    EXPECT_NE(msg.find("'" + bad + "'"), std::string::npos) << msg;
  }
}

TEST(ParseSigmas, KeepsTheYawSigmaUnwrapped) {
  // Through parse_pose a yaw sigma of 2 pi became 0 (and 4 a negative number).
  const Eigen::Vector3d s = parse_sigmas("0.1,0.2,6.283185307179586", "--init-sigma");
  EXPECT_DOUBLE_EQ(s[0], 0.1);
  EXPECT_DOUBLE_EQ(s[1], 0.2);
  EXPECT_DOUBLE_EQ(s[2], 2.0 * kPi);
  EXPECT_DOUBLE_EQ(parse_sigmas("0,0,4", "--init-sigma")[2], 4.0);
  EXPECT_TRUE(parse_sigmas("0,0,0", "--init-sigma").isZero(0.0));
}

TEST(ParseSigmas, RejectsNegativeNonFiniteAndMalformed) {
  for (const std::string bad : {"0.1,-0.1,0.05", "-0.1,0.1,0.05", "0.1,0.1,-1e-9", "0.1,0.1,inf",
                                "nan,0.1,0.1", "0.1,0.1", "0.1,0.1,0.1,0.1", "x,0.1,0.1"}) {
    const std::string msg = config_error([&] { (void)parse_sigmas(bad, "--init-sigma"); });
    EXPECT_NE(msg.find("--init-sigma: expected three standard deviations sx,sy,syaw, finite and "
                       ">= 0"),
              std::string::npos)
        << "'" << bad << "': " << msg;
    EXPECT_NE(msg.find("'" + bad + "'"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace vdtnav::tools
