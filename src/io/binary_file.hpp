#pragma once
// Internal (not installed): the pieces of vdtnav's binary map files (.svdt, .umap): CRC-32,
// little-endian fields of a header, a file written whole or not at all, and a file mapped
// read-only.

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <zlib.h>

#include "vdtnav/core/error.hpp"

namespace vdtnav::binary_file {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the map files map native arrays: little-endian hosts only");

/// zlib's CRC-32 of n bytes, continuing `crc`.
inline std::uint32_t crc_of(const unsigned char* p, std::size_t n,
                            std::uint32_t crc = static_cast<std::uint32_t>(crc32(0L, Z_NULL, 0))) {
  while (n > 0) {  // zlib takes uInt lengths
    const auto m = static_cast<uInt>(std::min<std::size_t>(n, 1U << 30));
    crc = static_cast<std::uint32_t>(crc32(crc, p, m));
    p += m;
    n -= m;
  }
  return crc;
}

template <typename T>
void put(std::vector<unsigned char>& h, std::size_t at, const T& v) {
  std::memcpy(h.data() + at, &v, sizeof(T));
}
template <typename T>
T get(const unsigned char* h, std::size_t at) {
  T v;
  std::memcpy(&v, h + at, sizeof(T));
  return v;
}

/// A piece of a file's body: n bytes at p.
using Piece = std::pair<const void*, std::size_t>;

/// Writes a file through `write(out)` to `path + ".tmp"` and renames it over `path`: a failed
/// write leaves any previous file untouched, and removes the temporary one. \throws IoError.
template <typename Write>
void write_atomically(const std::string& path, Write&& write) {
  namespace fs = std::filesystem;
  const std::string tmp = path + ".tmp";
  bool created = false;  // remove only what we made
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError(tmp + ": cannot open for writing: " + std::strerror(errno));
    created = true;
    write(out);
    out.close();
    if (!out) throw IoError(tmp + ": write failed");
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) throw IoError(path + ": cannot move " + tmp + " into place: " + ec.message());
  } catch (...) {
    std::error_code ec;
    if (created) fs::remove(tmp, ec);
    throw;
  }
}

/// Writes `head` and then `pieces` whole or not at all (write_atomically).
inline void write_atomically(const std::string& path, const std::vector<unsigned char>& head,
                             const std::vector<Piece>& pieces) {
  write_atomically(path, [&](std::ofstream& out) {
    out.write(reinterpret_cast<const char*>(head.data()),
              static_cast<std::streamsize>(head.size()));
    for (const auto& [p, n] : pieces)
      out.write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
  });
}

/// A file mapped read-only; `owner` unmaps it when the last holder lets go.
struct MappedFile {
  const unsigned char* data = nullptr;
  std::uint64_t size = 0;
  std::shared_ptr<const void> owner;
};

/// Maps `path` read-only. \throws IoError when it cannot be opened or mapped; FormatError when it
/// is empty (`what` names the kind of file expected).
inline MappedFile map_file(const std::string& path, const std::string& what) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw IoError(path + ": cannot open " + what + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int e = errno;
    ::close(fd);
    throw IoError(path + ": cannot stat: " + std::strerror(e));
  }
  const auto found = static_cast<std::uint64_t>(st.st_size);
  if (found == 0) {
    ::close(fd);
    throw FormatError(path, 0, "not a " + what + " (it is empty)");
  }
  void* addr = ::mmap(nullptr, found, PROT_READ, MAP_SHARED, fd, 0);
  const int map_errno = errno;
  ::close(fd);  // the mapping keeps the file
  if (addr == MAP_FAILED) throw IoError(path + ": cannot map: " + std::strerror(map_errno));
  MappedFile f;
  f.data = static_cast<const unsigned char*>(addr);
  f.size = found;
  f.owner = std::shared_ptr<const void>(
      addr, [found](const void* p) { ::munmap(const_cast<void*>(p), found); });
  return f;
}

}  // namespace vdtnav::binary_file
