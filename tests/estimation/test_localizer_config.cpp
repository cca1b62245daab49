// The settings file of `vdtnav localize --config`: every key written is read back to the same
// value, a file sets exactly the keys it names, and every mistake names file, line and key.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

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
  s.vdt_ekf.motion = MotionModelKind::kVelocity;  // the defaults' is the odometry increment
  s.vdt_ekf.noise.floor_r = 2e-3;
  s.vdt_ekf.start.loss = RobustLoss::kCauchy;
  s.vdt_ekf.start.search.window_yaw = 0.45;
  s.udt.map_sigma = 0.02;
  s.pf.seed = 4000000000u;
  s.pf.kld = true;
  s.threads = 3;
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
  EXPECT_EQ(back.threads, 3);
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
  // vdt-ekf's settings unchanged (on their own: the shared block printed with them is vdt-opt's
  // sensor model, which the file changed).
  const auto vdt_ekf_only = [](const LocalizerSettings& x) {
    LocalizerSettings t;
    t.vdt_ekf = x.vdt_ekf;
    return localizer_settings_yaml(t, "vdt-ekf");
  };
  EXPECT_EQ(vdt_ekf_only(s), vdt_ekf_only(defaults));
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
  // The top-level threads: key, an integer in [0, 4096].
  EXPECT_EQ(parse_localizer_config("threads: 2\n", "my.yaml", LocalizerSettings{}).threads, 2);
  EXPECT_NE(error_of("vdt-opt: {}\nthreads: -1\n")
                .find("my.yaml:2: threads: expected an integer in [0, 4096]"),
            std::string::npos)
      << error_of("vdt-opt: {}\nthreads: -1\n");
  EXPECT_NE(error_of("threads: {a: 1}\n").find("my.yaml:1: threads: expected an integer"),
            std::string::npos);
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

namespace vdtnav {
namespace {

/// Every sensor model of a 2D VDT method, named (what the shared sensor: block must reach).
std::vector<std::pair<std::string, VdtSensorModelOptions*>> vdt_sensors(LocalizerSettings& s) {
  return {{"vdt-opt", &s.vdt_opt.sensor},
          {"vdt-ekf", &s.vdt_ekf.sensor},
          {"vdt-ekf.start", &s.vdt_ekf.start.sensor},
          {"active-ekf.ekf", &s.active_ekf.ekf.sensor},
          {"active-ekf.ekf.start", &s.active_ekf.ekf.start.sensor},
          {"passive-ekf.ekf", &s.passive_ekf.ekf.sensor},
          {"passive-ekf.ekf.start", &s.passive_ekf.ekf.start.sensor}};
}

void expect_same_sensor(const VdtSensorModelOptions& a, const VdtSensorModelOptions& b,
                        const std::string& what) {
  EXPECT_EQ(a.gate_mode, b.gate_mode) << what;
  EXPECT_EQ(a.gate, b.gate) << what;
  EXPECT_EQ(a.residual, b.residual) << what;
  EXPECT_EQ(a.covariance, b.covariance) << what;
  EXPECT_EQ(a.map_sigma, b.map_sigma) << what;
  EXPECT_EQ(a.map_correlation_length, b.map_correlation_length) << what;
  EXPECT_EQ(a.map_pose_sigma, b.map_pose_sigma) << what;
}

/// Settings whose every sensor model differs from any printed one in every key: what a file is
/// read over when only the file may make the sensors right.
LocalizerSettings scrambled() {
  LocalizerSettings s;
  for (auto& [name, o] : vdt_sensors(s)) {
    o->gate_mode = GateMode::kNone;
    o->gate = 9.25;
    o->residual = ResidualMode::kNearestPoint;
    o->covariance = DisparityCovariance::kDiagonal;
    o->map_sigma = 0.777;
    o->map_correlation_length = 7.5;
    o->map_pose_sigma = 0.333;
  }
  return s;
}

TEST(LocalizerConfigSharedSensor, TheSharedBlockReachesEveryVdtMethodsSensorModel) {
  const LocalizerSettings defaults = log_settings();
  LocalizerSettings s = parse_localizer_config(
      "sensor:\n  gate: 0.7\n  map_correlation_length: 3.5\n  covariance: diagonal\n", "s.yaml",
      defaults);
  LocalizerSettings d = defaults;
  const auto targets = vdt_sensors(s);
  const auto before = vdt_sensors(d);
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const auto& [name, o] = targets[i];
    EXPECT_EQ(o->gate, 0.7) << name;
    EXPECT_EQ(o->map_correlation_length, 3.5) << name;
    EXPECT_EQ(o->covariance, DisparityCovariance::kDiagonal) << name;
    // Keys the block does not name keep each method's own value.
    EXPECT_EQ(o->map_sigma, before[i].second->map_sigma) << name;
    EXPECT_EQ(o->map_pose_sigma, before[i].second->map_pose_sigma) << name;
  }
  // Not the UDT baselines (no VDT sensor model) nor the 3D localizer (a 3D map).
  EXPECT_EQ(s.udt.gate, defaults.udt.gate);
  EXPECT_EQ(s.localize3d.optimizer.sensor.gate, defaults.localize3d.optimizer.sensor.gate);
  EXPECT_EQ(s.localize3d.optimizer.sensor.map_correlation_length, 1.0);
  // A mistake in the block names it.
  EXPECT_NE(error_of("sensor:\n  gate: 0.7\n  gte: 1\n").find("my.yaml:3: sensor.gte: unknown key"),
            std::string::npos)
      << error_of("sensor:\n  gate: 0.7\n  gte: 1\n");
}

TEST(LocalizerConfigSharedSensor, AMethodsOwnKeysOverrideTheSharedBlockKeyByKey) {
  // The method's block stands before the shared one in the file: the shared block is read first
  // wherever it stands.
  const LocalizerSettings s = parse_localizer_config(
      "vdt-ekf:\n  sensor: {gate: 0.2}\nactive-ekf:\n  ekf:\n    sensor: {map_sigma: 0.004}\n"
      "sensor: {gate: 0.7, gate_mode: norm, map_sigma: 0.01}\n",
      "o.yaml", LocalizerSettings{});
  EXPECT_EQ(s.vdt_ekf.sensor.gate, 0.2);
  EXPECT_EQ(s.vdt_ekf.sensor.gate_mode, GateMode::kNorm);  // the key it does not name: shared
  EXPECT_EQ(s.vdt_ekf.sensor.map_sigma, 0.01);
  EXPECT_EQ(s.vdt_ekf.start.sensor.gate, 0.7);
  EXPECT_EQ(s.vdt_opt.sensor.gate, 0.7);
  EXPECT_EQ(s.active_ekf.ekf.sensor.map_sigma, 0.004);
  EXPECT_EQ(s.active_ekf.ekf.sensor.gate, 0.7);
  EXPECT_EQ(s.passive_ekf.ekf.sensor.map_sigma, 0.01);
  // A file with per-method blocks only reads as it always did: nothing shared.
  const LocalizerSettings old =
      parse_localizer_config("vdt-opt:\n  sensor: {gate: 0.3}\n", "old.yaml", LocalizerSettings{});
  EXPECT_EQ(old.vdt_opt.sensor.gate, 0.3);
  EXPECT_EQ(old.vdt_ekf.sensor.gate, LocalizerSettings{}.vdt_ekf.sensor.gate);
  EXPECT_NE(old.vdt_ekf.sensor.gate, 0.3);
}

/// Settings whose methods' sensor models differ from vdt-opt's and from each other.
LocalizerSettings sensors_that_differ() {
  LocalizerSettings s = log_settings();
  s.vdt_opt.sensor.gate = 0.4375;
  s.vdt_ekf.sensor.map_sigma = 0.1 / 3.0;
  s.vdt_ekf.start.sensor.gate_mode = GateMode::kNorm;
  s.active_ekf.ekf.sensor.gate_mode = GateMode::kNone;
  s.passive_ekf.ekf.start.sensor.residual = ResidualMode::kNearestPoint;
  s.passive_ekf.ekf.sensor.map_pose_sigma = 0.0;
  return s;
}

TEST(LocalizerConfigSharedSensor, ThePrintedFileReadsBackToTheSameSettings) {
  for (const LocalizerSettings& s :
       {exact_map_settings(), log_settings(), cloud_settings(), sensors_that_differ(), changed()}) {
    const std::string yaml = localizer_settings_yaml(s);
    // The shared block is printed once at the top level.
    EXPECT_EQ(yaml.find("\nsensor:"), yaml.rfind("\nsensor:"));
    ASSERT_NE(yaml.find("\nsensor:"), std::string::npos);
    EXPECT_NE(
        yaml.find("\nvdt-opt:  # optimization localizer on the VDT (thesis 3.2)\n  sensor: {}"),
        std::string::npos)
        << "vdt-opt's sensor is the shared block";
    LocalizerSettings back = parse_localizer_config(yaml, "written", scrambled());
    LocalizerSettings want = s;
    const auto got = vdt_sensors(back);
    const auto expected = vdt_sensors(want);
    for (std::size_t i = 0; i < got.size(); ++i)
      expect_same_sensor(*got[i].second, *expected[i].second, got[i].first);
    EXPECT_EQ(localizer_settings_yaml(back), yaml);
    // One method's file (--print-config) reads back to that method's settings, over anything.
    for (const std::string& m : localizer_methods()) {
      const std::string one = localizer_settings_yaml(s, m);
      EXPECT_NE(one.find("\nsensor:"), std::string::npos) << m;
      LocalizerSettings b = parse_localizer_config(one, "one", scrambled());
      EXPECT_EQ(localizer_settings_yaml(b, m), one) << m;
      const auto gb = vdt_sensors(b);
      for (std::size_t i = 0; i < gb.size(); ++i) {
        if (gb[i].first.rfind(m, 0) == 0)
          expect_same_sensor(*gb[i].second, *expected[i].second, m + ": " + gb[i].first);
      }
    }
  }
  // Where the methods differ, their sensor: subsections list what differs, not every key.
  const std::string yaml = localizer_settings_yaml(sensors_that_differ());
  const std::size_t ekf = yaml.find("\nvdt-ekf:");
  const std::size_t ekf_sensor = yaml.find("\n  sensor:", ekf);
  const std::size_t ekf_next = yaml.find("\n  motion:", ekf);
  ASSERT_LT(ekf_sensor, ekf_next);
  const std::string block = yaml.substr(ekf_sensor, ekf_next - ekf_sensor);
  EXPECT_NE(block.find("map_sigma: 0.0333333"), std::string::npos) << block;
  EXPECT_NE(block.find("gate: 0.5 "), std::string::npos) << block;  // vdt-opt's is 0.4375
  EXPECT_EQ(block.find("gate_mode:"), std::string::npos) << block;
  EXPECT_EQ(block.find("map_correlation_length:"), std::string::npos) << block;
}

TEST(LocalizerConfig3d, TheDefaultsAreWhatLocalize3dRanWith) {
  // `vdtnav localize3d` before its section: cloud_settings()'s optimizer, --min-explained 0.3,
  // multi-start off with the attitude grid n = 2, held attitude NaN; lost at the window test's
  // default 0.5 since issue 57 counts only the beams through the map's surfaces (was 1 - 0.3).
  const VdtLocalizer3Options& o = LocalizerSettings{}.localize3d;
  EXPECT_EQ(o.optimizer.loss, RobustLoss::kCauchy);
  EXPECT_EQ(o.optimizer.loss_scale, 0.05);
  EXPECT_EQ(o.optimizer.max_iterations, 50);
  EXPECT_TRUE(o.optimizer.variance_factor);
  EXPECT_EQ(o.optimizer.function_tolerance, 1e-6);
  EXPECT_EQ(o.optimizer.coarse_threshold, -1.0);
  EXPECT_EQ(o.optimizer.sensor.map_correlation_length, 1.0);
  EXPECT_EQ(o.optimizer.sensor.map_pose_sigma, -1.0);
  EXPECT_FALSE(o.optimizer.four_dof);
  EXPECT_EQ(o.accept_fraction, 0.3);
  EXPECT_EQ(o.explained_distance, 0.1);
  EXPECT_DOUBLE_EQ(o.lost.lost_contradiction, LostDetectionOptions{}.lost_contradiction);
  EXPECT_EQ(o.lost.window, 5);
  EXPECT_FALSE(o.multi_start.enabled);
  EXPECT_EQ(o.multi_start.attitude_grid, 2);
  EXPECT_TRUE(std::isnan(o.held_attitude_sigma));
  EXPECT_EQ(o.sigma_translation_per_metre, 0.05);
  // cloud_settings() and log_settings() leave it so.
  EXPECT_EQ(cloud_settings().localize3d.accept_fraction, 0.3);
  EXPECT_EQ(localizer_settings_yaml(log_settings(), "localize3d"),
            localizer_settings_yaml(LocalizerSettings{}, "localize3d"));
}

TEST(LocalizerConfig3d, EveryKeyReachesTheLocalizersOptions) {
  const LocalizerSettings s = parse_localizer_config(
      "localize3d:\n"
      "  optimizer:\n"
      "    sensor: {gate: 0.8, map_correlation_length: 2.5}\n"
      "    max_iterations: 12\n"
      "    function_tolerance: 1e-5\n"
      "    loss: huber\n"
      "  sigma_translation_per_metre: 0.11\n"
      "  sigma_rotation_per_radian: 0.12\n"
      "  sigma_translation_per_second: 0.13\n"
      "  sigma_rotation_per_second: 0.14\n"
      "  sigma_imu_attitude: 0.015\n"
      "  held_attitude_sigma: 0.02\n"
      "  explained_distance: 0.16\n"
      "  accept_fraction: 0.45\n"
      "  multi_start:\n"
      "    enabled: true\n"
      "    explained_distance: 0.17\n"
      "    accept_fraction: 0.85\n"
      "    offset_translation: 0.3\n"
      "    offset_rotation: 0.15\n"
      "    truncation: 0.4\n"
      "    all_starts_below: 150\n"
      "    hops: 7\n"
      "    hop_seed: 9\n"
      "    attitude_grid: 3\n"
      "    attitude_grid_step: 0.05\n"
      "    screen_readings: 500\n"
      "    screen_keep: 4\n"
      "  lost:\n"
      "    window: 8\n"
      "    lost_contradiction: 0.6\n"
      "    found_contradiction: 0.25\n"
      "    doubt_contradiction: 0.35\n"
      "    doubt_rise: 0.2\n"
      "    sigmas: 2.5\n"
      "    baseline_scans: 40\n"
      "    min_judged: 0.1\n",
      "3d.yaml", LocalizerSettings{});
  const VdtLocalizer3Options& o = s.localize3d;
  EXPECT_EQ(o.optimizer.sensor.gate, 0.8);
  EXPECT_EQ(o.optimizer.sensor.map_correlation_length, 2.5);
  EXPECT_EQ(o.optimizer.max_iterations, 12);
  EXPECT_EQ(o.optimizer.function_tolerance, 1e-5);
  EXPECT_EQ(o.optimizer.loss, RobustLoss::kHuber);
  EXPECT_EQ(o.optimizer.variance_factor, true);  // not named: the default kept
  EXPECT_EQ(o.sigma_translation_per_metre, 0.11);
  EXPECT_EQ(o.sigma_rotation_per_radian, 0.12);
  EXPECT_EQ(o.sigma_translation_per_second, 0.13);
  EXPECT_EQ(o.sigma_rotation_per_second, 0.14);
  EXPECT_EQ(o.sigma_imu_attitude, 0.015);
  EXPECT_EQ(o.held_attitude_sigma, 0.02);
  EXPECT_EQ(o.explained_distance, 0.16);
  EXPECT_EQ(o.accept_fraction, 0.45);
  const MultiStartOptions& m = o.multi_start;
  EXPECT_TRUE(m.enabled);
  EXPECT_EQ(m.explained_distance, 0.17);
  EXPECT_EQ(m.accept_fraction, 0.85);
  EXPECT_EQ(m.offset_translation, 0.3);
  EXPECT_EQ(m.offset_rotation, 0.15);
  EXPECT_EQ(m.truncation, 0.4);
  EXPECT_EQ(m.all_starts_below, 150u);
  EXPECT_EQ(m.hops, 7);
  EXPECT_EQ(m.hop_seed, 9u);
  EXPECT_EQ(m.attitude_grid, 3);
  EXPECT_EQ(m.attitude_grid_step, 0.05);
  EXPECT_EQ(m.screen_readings, 500u);
  EXPECT_EQ(m.screen_keep, 4);
  const LostDetectionOptions& l = o.lost;
  EXPECT_EQ(l.window, 8);
  EXPECT_EQ(l.lost_contradiction, 0.6);
  EXPECT_EQ(l.found_contradiction, 0.25);
  EXPECT_EQ(l.doubt_contradiction, 0.35);
  EXPECT_EQ(l.doubt_rise, 0.2);
  EXPECT_EQ(l.sigmas, 2.5);
  EXPECT_EQ(l.baseline_scans, 40);
  EXPECT_EQ(l.min_judged, 0.1);
  EXPECT_NO_THROW(l.validate());
  // The 2D methods are untouched, and the section is printed and read back alone.
  EXPECT_EQ(localizer_settings_yaml(s, "vdt-opt"),
            localizer_settings_yaml(LocalizerSettings{}, "vdt-opt"));
  const std::string one = localizer_settings_yaml(s, "localize3d");
  EXPECT_NE(one.find("\nlocalize3d:"), std::string::npos);
  EXPECT_EQ(one.find("\nvdt-opt:"), std::string::npos);
  EXPECT_EQ(one.find("\nsensor:"), std::string::npos);
  EXPECT_EQ(one.find("\nrecovery:"), std::string::npos);
  const LocalizerSettings back = parse_localizer_config(one, "one", LocalizerSettings{});
  EXPECT_EQ(localizer_settings_yaml(back, "localize3d"), one);
  EXPECT_EQ(back.localize3d.lost.window, 8);
  EXPECT_EQ(back.localize3d.multi_start.hop_seed, 9u);
}

TEST(LocalizerConfig3d, HeldAttitudeSigmaIsANumberOrNan) {
  LocalizerSettings given;
  given.localize3d.held_attitude_sigma = 0.02;
  // The default NaN is printed so that it reads back to NaN (over a number).
  const std::string yaml = localizer_settings_yaml(LocalizerSettings{}, "localize3d");
  EXPECT_NE(yaml.find("held_attitude_sigma: .nan"), std::string::npos) << yaml;
  EXPECT_TRUE(std::isnan(parse_localizer_config(yaml, "y", given).localize3d.held_attitude_sigma));
  EXPECT_TRUE(
      std::isnan(parse_localizer_config("localize3d: {held_attitude_sigma: .nan}\n", "y", given)
                     .localize3d.held_attitude_sigma));
  EXPECT_EQ(parse_localizer_config("localize3d: {held_attitude_sigma: 0.015}\n", "y", {})
                .localize3d.held_attitude_sigma,
            0.015);
  // A number is printed as one and read back.
  const std::string number = localizer_settings_yaml(given, "localize3d");
  EXPECT_NE(number.find("held_attitude_sigma: 0.02 "), std::string::npos);
  EXPECT_EQ(parse_localizer_config(number, "y", {}).localize3d.held_attitude_sigma, 0.02);
  // Infinity is not; other keys still refuse NaN.
  EXPECT_NE(
      error_of("localize3d:\n  held_attitude_sigma: .inf\n")
          .find("my.yaml:2: localize3d.held_attitude_sigma: expected a finite number or .nan"),
      std::string::npos)
      << error_of("localize3d:\n  held_attitude_sigma: .inf\n");
  EXPECT_NE(error_of("localize3d:\n  sigma_imu_attitude: .nan\n")
                .find("localize3d.sigma_imu_attitude: expected a finite number"),
            std::string::npos);
}

TEST(LocalizerConfig3d, MistakesNameFileLineAndKeyPath) {
  EXPECT_NE(error_of("localize3d:\n  lost:\n    windw: 3\n")
                .find("my.yaml:3: localize3d.lost.windw: unknown key (known: window,"),
            std::string::npos)
      << error_of("localize3d:\n  lost:\n    windw: 3\n");
  EXPECT_NE(error_of("localize3d:\n  optimizer:\n    sensor:\n      gat: 1\n")
                .find("my.yaml:4: localize3d.optimizer.sensor.gat: unknown key"),
            std::string::npos);
  EXPECT_NE(error_of("localize3d:\n  four_dof: true\n").find("localize3d.four_dof: unknown key"),
            std::string::npos)
      << "--dof chooses the mode";
  EXPECT_NE(error_of("localize3d:\n  multi_start: {hops: many}\n")
                .find("my.yaml:2: localize3d.multi_start.hops: expected an integer"),
            std::string::npos);
}

}  // namespace
}  // namespace vdtnav
