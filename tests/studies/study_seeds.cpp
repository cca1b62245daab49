// vdtnav_study_seeds EXPECTED.yaml DATA_DIR OUT_DIR...: the studies' figures over several runs
// (scripts/seeds.sh: one output folder per seed, named seed_N) as a Markdown table with how many
// runs meet each target (study_figures.hpp, seeds_table).
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "study_figures.hpp"
#include "vdtnav/core/error.hpp"

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s EXPECTED.yaml DATA_DIR OUT_DIR...\n", argv[0]);
    return 2;
  }
  std::vector<std::string> dirs, labels;
  for (int i = 3; i < argc; ++i) {
    dirs.emplace_back(argv[i]);
    std::string name = std::filesystem::path(argv[i]).lexically_normal().filename().string();
    if (name.empty()) name = std::filesystem::path(argv[i]).parent_path().filename().string();
    for (char& ch : name) ch = ch == '_' ? ' ' : ch;
    labels.push_back(name);
  }
  try {
    std::fputs(vdtnav::studies::seeds_table(argv[1], dirs, labels, argv[2]).c_str(), stdout);
    return 0;
  } catch (const vdtnav::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
