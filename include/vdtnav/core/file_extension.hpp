#pragma once
/// \file
/// \brief The lower-case extension of a file name, by which the readers choose a format.

#include <algorithm>
#include <cctype>
#include <string>

namespace vdtnav {

/// \return the extension of `path`'s last component with its dot, lower-case (".pcd"); "" when
/// it has none (a dot in a folder name does not count).
[[nodiscard]] inline std::string lower_extension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace vdtnav
