// The settings file of `vdtnav localize --config`: every key written is read back to the same
// value, a file sets exactly the keys it names, and every mistake names file, line and key.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_config.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"

namespace vdtnav {
namespace {

std::string error_of(const std::string& text) {
  try {
    (void)parse_localizer_config(text, "my.yaml", LocalizerSettings{});
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

/// Settings that differ from the defaults in a key of every kind and every nesting level.
LocalizerSettings changed() {
  LocalizerSettings s;
  s.vdt_opt.sensor.gate = 0.3125;
  s.vdt_opt.sensor.gate_mode = GateMode::kNorm;
  s.vdt_opt.loss = RobustLoss::kHuber;
  s.vdt_opt.loss_scale = 0.1 / 3.0;  // not short in decimal: the writer must round-trip it
  s.vdt_opt.max_iterations = 77;
  s.vdt_opt.variance_factor = true;
  s.vdt_opt.search.max_beams = 123;
  s.vdt_opt.search.odometry_noise.a_tt = 0.07;
  s.vdt_opt.bridge.enabled = false;
  s.vdt_ekf.motion = MotionModelKind::kOdometryIncrement;
  s.vdt_ekf.noise.floor_r = 2e-3;
  s.vdt_ekf.start.loss = RobustLoss::kCauchy;
  s.vdt_ekf.start.search.window_yaw = 0.45;
  s.udt.map_sigma = 0.02;
  s.pf.seed = 4000000000u;
  s.pf.kld = true;
  return s;
}

TEST(LocalizerConfig, EveryWrittenKeyReadsBackToTheSameValue) {
  const LocalizerSettings s = changed();
  const std::string yaml = localizer_settings_yaml(s);
  EXPECT_NE(yaml, localizer_settings_yaml(LocalizerSettings{}));
  // Read over settings that differ everywhere it matters: only the file can make them equal.
  const LocalizerSettings back = parse_localizer_config(yaml, "written", LocalizerSettings{});
  EXPECT_EQ(localizer_settings_yaml(back), yaml);
  EXPECT_EQ(back.vdt_opt.loss_scale, s.vdt_opt.loss_scale);  // bit for bit
  EXPECT_EQ(back.pf.seed, 4000000000u);
  EXPECT_EQ(back.vdt_ekf.start.search.window_yaw, 0.45);
  EXPECT_EQ(back.vdt_opt.search.max_beams, 123u);
}

TEST(LocalizerConfig, AFileSetsOnlyTheKeysItNames) {
  const LocalizerSettings defaults = log_settings();
  const LocalizerSettings s = parse_localizer_config(
      "vdt-opt:\n  sensor: {gate: 0.25}\n  search:\n    odometry_noise: {a_rr: 0.2}\n"
      "udt: {gate: 0.4}\n",
      "t.yaml", defaults);
  EXPECT_EQ(s.vdt_opt.sensor.gate, 0.25);
  EXPECT_EQ(s.vdt_opt.search.odometry_noise.a_rr, 0.2);
  EXPECT_EQ(s.udt.gate, 0.4);
  // Everything else stays what it was read over (here the log settings, not the struct's).
  EXPECT_EQ(s.vdt_opt.loss, RobustLoss::kCauchy);
  EXPECT_EQ(s.vdt_opt.max_iterations, defaults.vdt_opt.max_iterations);
  EXPECT_EQ(s.vdt_opt.search.odometry_noise.a_tt, defaults.vdt_opt.search.odometry_noise.a_tt);
  EXPECT_EQ(localizer_settings_yaml(s, "vdt-ekf"), localizer_settings_yaml(defaults, "vdt-ekf"));
  // An empty file is the defaults.
  EXPECT_EQ(localizer_settings_yaml(parse_localizer_config("", "e.yaml", defaults)),
            localizer_settings_yaml(defaults));
}

TEST(LocalizerConfig, OneMethodsSectionOnly) {
  const std::string opt = localizer_settings_yaml(LocalizerSettings{}, "vdt-opt");
  EXPECT_EQ(opt.find("\nvdt-ekf:"), std::string::npos);
  EXPECT_NE(opt.find("\nvdt-opt:"), std::string::npos);
  EXPECT_NE(localizer_settings_yaml(LocalizerSettings{}, "udt-ekf").find("\nudt:"),
            std::string::npos);
  EXPECT_THROW((void)localizer_settings_yaml(LocalizerSettings{}, "amcl"), ConfigError);
  // Every key line documents itself.
  EXPECT_NE(opt.find("gate: 0.5"), std::string::npos);
  EXPECT_NE(opt.find("# [m] alpha of (3.3)"), std::string::npos);
}

TEST(LocalizerConfig, TheDocumentedListingIsWhatTheWriterPrints) {
  // docs/settings.md holds the listing of every key for every method with log_settings(), the
  // defaults `vdtnav localize` runs with; it must be the writer's output, byte for byte (after a
  // change of a key or default: paste localizer_settings_yaml(log_settings(), "") there).
  std::ifstream in(std::string(VDTNAV_SOURCE_DIR) + "/docs/settings.md");
  ASSERT_TRUE(in) << "docs/settings.md not found";
  std::stringstream text;
  text << in.rdbuf();
  const std::string doc = text.str();
  const std::size_t begin = doc.find("# vdtnav localizer settings:");
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = doc.find("```", begin);
  ASSERT_NE(end, std::string::npos);
  EXPECT_EQ(doc.substr(begin, end - begin), localizer_settings_yaml(log_settings(), ""));
}

TEST(LocalizerConfig, MistakesNameFileLineAndKey) {
  EXPECT_NE(error_of("vdt-opt:\n  search:\n    explaind_distance: 0.1\n")
                .find("my.yaml:3: vdt-opt.search.explaind_distance: unknown key (known: enabled, "
                      "explained_distance"),
            std::string::npos)
      << error_of("vdt-opt:\n  search:\n    explaind_distance: 0.1\n");
  EXPECT_NE(error_of("vdt-opt:\n  loss_scale: abc\n")
                .find("my.yaml:2: vdt-opt.loss_scale: expected a finite number, got 'abc'"),
            std::string::npos);
  EXPECT_NE(error_of("vdt-opt:\n  loss_scale: .nan\n").find("expected a finite number"),
            std::string::npos);
  EXPECT_NE(
      error_of("pf:\n  particles: 2.5\n").find("my.yaml:2: pf.particles: expected an integer"),
      std::string::npos);
  EXPECT_NE(error_of("vdt-opt:\n  loss: tukey\n")
                .find("my.yaml:2: vdt-opt.loss: expected one of none, huber, cauchy, got 'tukey'"),
            std::string::npos);
  EXPECT_NE(error_of("vdt-opt:\n  bridge: {enabled: maybe}\n").find("expected true or false"),
            std::string::npos);
  EXPECT_NE(error_of("amcl:\n  particles: 10\n").find("my.yaml:1: unknown section 'amcl'"),
            std::string::npos);
  EXPECT_NE(error_of("vdt-opt: [1, 2]\n").find("vdt-opt: expected a mapping"), std::string::npos);
  EXPECT_NE(error_of("vdt-opt:\n  gate: 0.2\n").find("vdt-opt.gate: unknown key"),
            std::string::npos);  // gate belongs to sensor:
  EXPECT_NE(error_of("vdt-opt: {loss: cauchy\n").find("my.yaml:"), std::string::npos);
  EXPECT_NE(error_of("vdt-opt:\n  max_iterations:\n").find("expected a value"), std::string::npos);
  EXPECT_THROW((void)load_localizer_config("/nonexistent/settings.yaml", LocalizerSettings{}),
               ConfigError);
}

}  // namespace
}  // namespace vdtnav

namespace vdtnav {
namespace {

TEST(LocalizerConfig, KeysThatAreMappingsOrListsAreErrorsNotCrashes) {
  // fuzz_localizer_config (10^6 runs by hand): a complex key (`? ...`) in a section made yaml-cpp
  // throw a bad conversion past every catch of vdtnav::Error. The input as found, then the two
  // levels by hand.
  const std::string found =
      std::string(VDTNAV_FUZZ_REGRESSIONS) + "/localizer_config-key-not-scalar.yaml";
  try {
    (void)load_localizer_config(found, LocalizerSettings{});
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("key-not-scalar.yaml:"), std::string::npos) << e.what();
  }
  for (const char* text : {"? [vdt-opt, pf]\n: {}\n", "vdt-opt:\n  ? {gate: 1}\n  : 2\n"}) {
    try {
      (void)parse_localizer_config(text, "my.yaml", LocalizerSettings{});
      ADD_FAILURE() << text;
    } catch (const ConfigError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("my.yaml:"), std::string::npos) << msg;
      EXPECT_NE(msg.find("expected a"), std::string::npos) << msg;
    }
  }
}

}  // namespace
}  // namespace vdtnav
