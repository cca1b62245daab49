#include "staged_output.hpp"

#include <unistd.h>

#include <filesystem>

#include "vdtnav/core/error.hpp"

namespace vdtnav::tools {

namespace {

namespace fs = std::filesystem;

/// `PARENT/.STEM.vdtnav-PID.EXT`: hidden, in the same folder (and file system) as the final name,
/// with its extension (writers that choose the format by it still do).
fs::path temporary_for(const std::string& final_path) {
  const fs::path p(final_path);
  fs::path parent = p.parent_path();
  if (parent.empty()) parent = ".";
  std::error_code ec;
  if (!fs::is_directory(parent, ec)) {
    throw IoError(final_path + ": cannot write there, the folder " + parent.string() +
                  " does not exist");
  }
  return parent / ("." + p.stem().string() + ".vdtnav-" + std::to_string(::getpid()) +
                   p.extension().string());
}

void rename_or_throw(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::rename(from, to, ec);
  if (ec)
    throw IoError(to.string() + ": cannot write it (rename from " + from.string() + ": " +
                  ec.message() + ")");
}

}  // namespace

StagedOutputs::~StagedOutputs() {
  for (const Entry& e : entries_) {
    std::error_code ec;  // best effort: nothing to report from a destructor
    fs::remove_all(e.temporary, ec);
  }
}

std::string StagedOutputs::file(const std::string& final_path) {
  const fs::path t = temporary_for(final_path);
  entries_.push_back({t.string(), final_path, false});
  return t.string();
}

std::string StagedOutputs::folder(const std::string& final_dir) {
  fs::path clean = fs::path(final_dir).lexically_normal();
  if (!clean.has_filename()) clean = clean.parent_path();  // "out/" -> "out"
  const fs::path t = temporary_for(clean.string());
  std::error_code ec;
  fs::remove_all(t, ec);
  if (!fs::create_directory(t, ec) || ec) {
    throw IoError(final_dir + ": cannot create the output folder (" + t.string() + ": " +
                  ec.message() + ")");
  }
  entries_.push_back({t.string(), clean.string(), true});
  return t.string();
}

void StagedOutputs::commit() {
  for (Entry& e : entries_) {
    std::error_code ec;
    if (!e.is_folder || !fs::exists(e.final_path, ec)) {
      rename_or_throw(e.temporary, e.final_path);
    } else {
      if (!fs::is_directory(e.final_path, ec)) {
        throw IoError(e.final_path + ": exists and is not a folder");
      }
      for (const fs::directory_entry& f : fs::directory_iterator(e.temporary)) {
        rename_or_throw(f.path(), fs::path(e.final_path) / f.path().filename());
      }
      fs::remove_all(e.temporary, ec);
    }
  }
  entries_.clear();
}

}  // namespace vdtnav::tools
