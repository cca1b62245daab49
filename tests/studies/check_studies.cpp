// vdtnav_check_studies EXPECTED.yaml OUT_DIR DATA_DIR: the main job's headline figures against
// the recorded ones (study_figures.hpp). Prints every figure; exits 1 when one is off.
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
    int failed = 0, skipped = 0;
    for (const auto& c : checks) {
      const char* verdict = c.skipped ? "skip" : c.passed ? "ok  " : "FAIL";
      std::printf("%s %-38s %-40s %-24s", verdict, c.file.c_str(), c.row.c_str(), c.column.c_str());
      if (!c.skipped && c.message.empty()) std::printf(" %-12.6g", c.measured);
      if (!c.target.empty()) std::printf(" target %s", c.target.c_str());
      if (!c.message.empty()) std::printf(" (%s)", c.message.c_str());
      if (!c.reason.empty() && !c.skipped && c.message.empty() && !c.within_target)
        std::printf("\n     accepted outside its target: %s", c.reason.c_str());
      std::printf("\n");
      failed += !c.passed;
      skipped += c.skipped;
    }
    std::printf("%zu figures: %zu within their recorded range, %d skipped (no data), %d off\n",
                checks.size(), checks.size() - failed - skipped, skipped, failed);
    return failed == 0 ? 0 : 1;
  } catch (const vdtnav::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
