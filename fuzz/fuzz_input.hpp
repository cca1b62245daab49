#pragma once
// The fuzz targets' common part: the input written to a file of this process (the parsers read
// files, as the library's users call them), and the one exception a parser may throw on bad
// input — vdtnav::Error (IoError, FormatError, ConfigError). Anything else escapes and is a
// finding, as are crashes, hangs, leaks and sanitizer reports.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace vdtnav::fuzz {

/// \return a folder of this process under the temporary directory (made once).
inline const std::filesystem::path& folder() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path d =
        std::filesystem::temp_directory_path() / ("vdtnav_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

/// \brief Writes `size` bytes to folder()/name and returns the path.
inline std::string write(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const std::filesystem::path p = folder() / name;
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return p.string();
}

inline std::string write(const std::string& text, const std::string& name) {
  return write(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), name);
}

}  // namespace vdtnav::fuzz
