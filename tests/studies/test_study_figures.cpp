// The studies' figure check (study_figures.hpp) on a small output folder: a figure in range
// passes, one that moved fails with the file, row and column named, a missing study or row
// fails, a real-data figure without its data is skipped; a figure that crosses its target fails
// unless marked known_short (naming an issue), and a marked one passes with its reason in the
// report's list of shortfalls; an expectations file that records a value outside its target
// without the mark is refused, and so is a ceiling beyond its target. The checked-in
// expected.yaml parses.
#include "study_figures.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "vdtnav/core/error.hpp"

namespace vdtnav::studies {
namespace {

namespace fs = std::filesystem;

fs::path dir() {
  const fs::path d = fs::path(VDTNAV_TEST_TMP) / ("studies_" + std::to_string(::getpid()));
  fs::create_directories(d / "out/intel_lab");
  return d;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

/// Expects d/bad.yaml to be refused with a FormatError whose message contains `message`.
void expect_refused(const fs::path& d, const std::string& message) {
  try {
    (void)check_study_figures((d / "bad.yaml").string(), (d / "out").string(), d.string());
    FAIL() << "no error";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

TEST(StudyFigures, InRangePassesMovedFailsMissingFailsNoDataSkips) {
  const fs::path d = dir();
  write(d / "out/intel_lab/table.csv",
        "method,relations,rel_trans_mean_m,lost\ngmapping (reference),58,0.0376,0\n"
        "vdt-opt,58,0.0295,0\nvdt-ekf,58,0.0587,3\n");
  write(d / "expected.yaml", R"(
- file: intel_lab/table.csv
  row: {method: vdt-opt}
  column: rel_trans_mean_m
  value: 0.0295
  tolerance: 0.001
  target: "<= 0.035"
- file: intel_lab/table.csv
  row: {method: vdt-ekf}
  column: lost
  value: 0
  target: "<= 0"
  known_short: a test of a failing figure, issue 1
- file: intel_lab/table.csv
  row: {method: vdt-ekf}
  column: rel_trans_mean_m
  max: 0.05
- file: intel_lab/table.csv
  row: {method: pf}
  column: lost
  value: 0
- file: uav_camera/table.csv
  row: {method: vdt-opt}
  column: rmse
  value: 1
- file: turtlebot_lidar_hospital/table.csv
  row: {method: vdt-opt}
  column: rmse
  value: 1
  skip_without: stage_maps/hospital_section.png
)");
  const auto c =
      check_study_figures((d / "expected.yaml").string(), (d / "out").string(), d.string());
  ASSERT_EQ(c.size(), 6U);
  EXPECT_TRUE(c[0].passed) << c[0].message;
  EXPECT_NEAR(c[0].measured, 0.0295, 1e-12);
  EXPECT_FALSE(c[1].passed);  // 3 lost, recorded 0
  EXPECT_EQ(c[1].message, "3 is not 0 +- 0");
  EXPECT_FALSE(c[2].passed);  // 0.0587 > max 0.05
  EXPECT_FALSE(c[3].passed);  // no row method=pf
  EXPECT_EQ(c[3].message, "0 rows with method=pf");
  EXPECT_FALSE(c[4].passed);  // the study did not run
  EXPECT_NE(c[4].message.find("uav_camera/table.csv"), std::string::npos) << c[4].message;
  EXPECT_TRUE(c[5].skipped);
  EXPECT_TRUE(c[5].passed);
}

TEST(StudyFigures, AFigureThatCrossesItsTargetFailsUnlessMarkedKnownShort) {
  // The same measured figures, 0.0330 m against a target of <= 0.030, inside the recorded
  // tolerance both times: unmarked it fails; marked, it passes and the report lists it with its
  // distance and reason. A marked figure that meets its target passes and says the mark can go.
  const fs::path d = dir();
  write(d / "out/intel_lab/table.csv",
        "method,rel_trans_mean_m,anees\nvdt-opt,0.0330,3.0\nvdt-ekf,0.0310,3.5\n");
  const std::string entry = R"y(
- file: intel_lab/table.csv
  row: {method: vdt-opt}
  column: rel_trans_mean_m
  value: 0.0290
  tolerance: 0.005
  target: "<= 0.030"
)y";
  write(d / "unmarked.yaml", entry);
  const auto u =
      check_study_figures((d / "unmarked.yaml").string(), (d / "out").string(), d.string());
  ASSERT_EQ(u.size(), 1U);
  EXPECT_FALSE(u[0].passed);
  EXPECT_EQ(u[0].message, "0.033 is outside its target <= 0.030 (not marked known_short)");
  EXPECT_NE(report(u).find("FAIL"), std::string::npos);
  EXPECT_NE(report(u).find("1 failed"), std::string::npos) << report(u);

  write(d / "marked.yaml", entry + R"y(  known_short: "a test of a shortfall (issue 7)"
- file: intel_lab/table.csv
  row: {method: vdt-ekf}
  column: anees
  value: 3.5
  tolerance: 0.1
  target: "in [2.5, 3.2]"
  known_short: "over-confident (issue 8)"
- file: intel_lab/table.csv
  row: {method: vdt-opt}
  column: anees
  value: 3.0
  tolerance: 0.1
  target: "in [2.5, 3.2]"
  known_short: "was short (issue 9)"
)y");
  const auto m =
      check_study_figures((d / "marked.yaml").string(), (d / "out").string(), d.string());
  ASSERT_EQ(m.size(), 3U);
  EXPECT_TRUE(m[0].passed) << m[0].message;
  EXPECT_FALSE(m[0].within_target);
  EXPECT_NEAR(m[0].distance, 0.003, 1e-12);
  EXPECT_TRUE(m[1].passed) << m[1].message;
  EXPECT_NEAR(m[1].distance, 0.3, 1e-12);
  EXPECT_TRUE(m[2].passed);
  EXPECT_TRUE(m[2].within_target);
  const std::string r = report(m);
  EXPECT_NE(r.find("- intel_lab/table.csv [method=vdt-opt] rel_trans_mean_m: 0.033, target <= "
                   "0.030, short by 0.003: a test of a shortfall (issue 7)"),
            std::string::npos)
      << r;
  EXPECT_NE(r.find("anees: 3.5, target in [2.5, 3.2], short by 0.3: over-confident (issue 8)"),
            std::string::npos)
      << r;
  EXPECT_NE(r.find("meets its target now: the mark can go"), std::string::npos) << r;
  EXPECT_EQ(r.find("was short (issue 9)"), std::string::npos) << r;  // not listed as short
  EXPECT_NE(r.find("3 figures: 3 pass (2 of them known short of their target)"), std::string::npos)
      << r;

  // A mark must name the issue that will close it.
  write(d / "bad.yaml", entry + "  known_short: \"someday\"\n");
  expect_refused(d, "known_short must name the issue that will close it");
}

TEST(StudyFigures, ATargetMetOnSeedOneOnlyIsShort) {
  // Recorded on seeds 1-5, the target met on seed 1 only: refused unmarked, although this run
  // (seed 1) meets it; marked, it passes as "short" and is listed with its seeds count, without
  // the "mark can go" of a figure that meets its target.
  const fs::path d = dir();
  write(d / "out/intel_lab/table.csv", "method,anees\nvdt-opt,2.98\n");
  const std::string entry = R"y(
- file: intel_lab/table.csv
  row: {method: vdt-opt}
  column: anees
  value: 2.98
  tolerance: 0.8
  target: "in [2.89, 3.11]"
  seeds: [2.98, 3.76, 3.46, 3.29, 3.43]
)y";
  write(d / "bad.yaml", entry);
  expect_refused(d, "the target 'in [2.89, 3.11]' is met on 1 of 5 seeds: mark it known_short");
  write(d / "marked.yaml", entry + "  known_short: \"over-confident on seeds 2-5, issue 60\"\n");
  const auto m =
      check_study_figures((d / "marked.yaml").string(), (d / "out").string(), d.string());
  ASSERT_EQ(m.size(), 1U);
  EXPECT_TRUE(m[0].passed);
  EXPECT_TRUE(m[0].within_target);
  EXPECT_EQ(m[0].seeds_met, 1);
  EXPECT_TRUE(m[0].short_of_target());
  const std::string r = report(m);
  EXPECT_EQ(r.rfind("short intel_lab/table.csv", 0), 0U) << r;
  EXPECT_NE(r.find("anees: 2.98, target in [2.89, 3.11], met on 1 of 5 seeds: over-confident on "
                   "seeds 2-5, issue 60"),
            std::string::npos)
      << r;
  EXPECT_EQ(r.find("the mark can go"), std::string::npos) << r;
  // Met on 4 of 5: not short, and needs no mark.
  write(d / "four.yaml", R"y(
- file: intel_lab/table.csv
  row: {method: vdt-opt}
  column: anees
  value: 2.98
  tolerance: 0.8
  target: "in [2.89, 3.11]"
  seeds: [2.98, 3.0, 3.1, 2.9, 3.43]
)y");
  const auto f = check_study_figures((d / "four.yaml").string(), (d / "out").string(), d.string());
  ASSERT_EQ(f.size(), 1U);
  EXPECT_TRUE(f[0].passed);
  EXPECT_FALSE(f[0].short_of_target());
}

TEST(StudyFigures, AValueOutsideItsTargetNeedsTheMark) {
  const fs::path d = dir();
  write(d / "bad.yaml", R"(
- file: intel_lab/table.csv
  row: {method: vdt-opt}
  column: rel_trans_mean_m
  value: 0.04
  tolerance: 0.001
  target: "<= 0.035"
)");
  expect_refused(d,
                 "bad.yaml:2: the recorded value is outside its target '<= 0.035': mark it "
                 "known_short");
  write(d / "in.yaml", R"(
- file: x.csv
  row: {method: a}
  column: c
  value: 3.1
  target: "in [2.81, 3.20]"
)");
  EXPECT_NO_THROW(
      (void)check_study_figures((d / "in.yaml").string(), (d / "out").string(), d.string()));
}

TEST(StudyFigures, ACeilingBeyondItsTargetNeedsTheMarkAndSaysWhenItIsUsed) {
  const fs::path d = dir();
  write(d / "out/intel_lab/table.csv", "method,cpu_ms_max\nvdt-opt,130\nvdt-ekf,40\n");
  write(d / "bad.yaml", R"(
- file: intel_lab/table.csv
  row: {method: vdt-opt}
  column: cpu_ms_max
  max: 250
  target: "<= 100"
)");
  expect_refused(d, "bad.yaml:2: min / max admit values outside the target");
  write(d / "ok.yaml", R"(
- file: intel_lab/table.csv
  row: {method: vdt-opt}
  column: cpu_ms_max
  max: 250
  target: "<= 100"
  known_short: a shared machine's noise, issue 34
- file: intel_lab/table.csv
  row: {method: vdt-ekf}
  column: cpu_ms_max
  max: 250
  target: "<= 100"
  known_short: a shared machine's noise, issue 34
- file: intel_lab/table.csv
  row: {method: vdt-ekf}
  column: cpu_ms_max
  max: 30
  target: "<= 100"
)");
  const auto c = check_study_figures((d / "ok.yaml").string(), (d / "out").string(), d.string());
  ASSERT_EQ(c.size(), 3U);
  EXPECT_TRUE(c[0].passed);  // 130 within the ceiling, outside the target: marked known short
  EXPECT_FALSE(c[0].within_target);
  EXPECT_TRUE(c[1].passed);  // 40 within both: the reason is not printed
  EXPECT_TRUE(c[1].within_target);
  EXPECT_FALSE(c[2].passed);  // 40 over a ceiling of 30
  EXPECT_EQ(c[2].message, "40 is not in [-inf, 30]");
}

TEST(StudyFigures, TheSeedsTableCountsTheRunsThatMeetEachTargetWhateverTheRecordedRange) {
  // Three runs: a figure inside its interval on two of them (one of which is off its recorded
  // value, so the check fails it, and the table still counts it as meeting the target), one
  // run without the study; a figure without a target is not listed.
  const fs::path d = dir();
  for (const char* s : {"seed_1", "seed_2", "seed_3"}) fs::create_directories(d / s / "uav_camera");
  write(d / "seed_1/uav_camera/table.csv", "method,anees,rmse_m\nvdt-opt,3.0,0.08\n");
  write(d / "seed_2/uav_camera/table.csv", "method,anees,rmse_m\nvdt-opt,2.9,0.12\n");
  write(d / "seed_3/uav_camera/table.csv", "method,anees,rmse_m\nvdt-opt,33.5,0.37\n");
  fs::create_directories(d / "seed_4");
  write(d / "seeds.yaml", R"(
- file: uav_camera/table.csv
  row: {method: vdt-opt}
  column: anees
  value: 3.0
  tolerance: 0.05
  target: "in [2.83, 3.16]"
- file: uav_camera/table.csv
  row: {method: vdt-opt}
  column: rmse_m
  value: 0.08
  tolerance: 0.01
)");
  const std::string md = seeds_table((d / "seeds.yaml").string(),
                                     {(d / "seed_1").string(), (d / "seed_2").string(),
                                      (d / "seed_3").string(), (d / "seed_4").string()},
                                     {"seed 1", "seed 2", "seed 3", "seed 4"}, d.string());
  EXPECT_NE(md.find("| study | row | figure | target | seed 1 | seed 2 | seed 3 | seed 4 |"),
            std::string::npos)
      << md;
  EXPECT_NE(
      md.find(
          "| uav_camera | method=vdt-opt | anees | in [2.83, 3.16] | 3 | 2.9 | 33.5 | — | 2/3 |"),
      std::string::npos)
      << md;
  EXPECT_EQ(md.find("rmse_m"), std::string::npos) << md;
}

TEST(StudyFigures, TheCheckedInExpectationsParse) {
  // Every entry well formed and every recorded value inside its target or marked known_short; the
  // figures themselves are checked by scripts/test.sh after the main job.
  const fs::path expected = fs::path(VDTNAV_SOURCE_DIR) / "tests/studies/expected.yaml";
  const auto c = check_study_figures(expected.string(), "/nonexistent", "/nonexistent");
  EXPECT_GT(c.size(), 20U);
}

}  // namespace
}  // namespace vdtnav::studies
