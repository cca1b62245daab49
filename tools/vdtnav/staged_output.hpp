#pragma once
/// \file
/// \brief Outputs that appear only when a run completes. Each file (or a sequence's folder) is
/// written under a temporary name beside its final one (same folder, so that the rename is
/// atomic) and renamed by commit(); a run that throws before commit() leaves nothing behind.

#include <string>
#include <vector>

namespace vdtnav::tools {

class StagedOutputs {
 public:
  StagedOutputs() = default;
  StagedOutputs(const StagedOutputs&) = delete;
  StagedOutputs& operator=(const StagedOutputs&) = delete;
  /// Removes every temporary not committed.
  ~StagedOutputs();

  /// \return the path to write the output `final_path` to (`DIR/.STEM.vdtnav-PID.EXT`).
  /// \throws IoError when the folder of `final_path` does not exist.
  [[nodiscard]] std::string file(const std::string& final_path);

  /// \return a new empty folder (`PARENT/.NAME.vdtnav-PID/`) whose entries become those of
  /// `final_dir`: the whole folder when `final_dir` does not exist, else file by file.
  /// \throws IoError when it cannot be created.
  [[nodiscard]] std::string folder(const std::string& final_dir);

  /// Renames every output to its final name, in the order they were staged. \throws IoError.
  void commit();

 private:
  struct Entry {
    std::string temporary, final_path;
    bool is_folder = false;
  };
  std::vector<Entry> entries_;
};

}  // namespace vdtnav::tools
