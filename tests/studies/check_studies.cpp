// vdtnav_check_studies EXPECTED.yaml OUT_DIR DATA_DIR: the main job's headline figures against
// the recorded ones and their targets (study_figures.hpp). Prints every figure and the known
// shortfalls; exits 1 when a figure is off its recorded range or outside an unmarked target.
#include <cstdio>

#include "study_figures.hpp"
#include "vdtnav/core/error.hpp"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s EXPECTED.yaml OUT_DIR DATA_DIR\n", argv[0]);
    return 2;
  }
  try {
    const auto checks = vdtnav::studies::check_study_figures(argv[1], argv[2], argv[3]);
    std::fputs(vdtnav::studies::report(checks).c_str(), stdout);
    int failed = 0;
    for (const auto& c : checks) failed += !c.passed;
    return failed == 0 ? 0 : 1;
  } catch (const vdtnav::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
