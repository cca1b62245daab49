// ROS 1 bags (format 2.0) read through Debian's rosbag_storage; their messages are decoded from
// ROS 1 serialization in ros1_serialization.cpp.
//
// rosbag_storage trusts the file: it follows offsets and lengths from the index without bounds
// checks, so a truncated or corrupt bag can make it read past its buffers. open() therefore first
// walks the records rosbag_storage will read when opening (the index at the end, each chunk's
// header and the index records after it), the same way it does, and checks every position,
// length, count and compression name against the file; only a bag that passes is handed to
// rosbag_storage. Any exception rosbag_storage still throws is rethrown
// as vdtnav::FormatError naming the file (or the topic and bag time for a message).

#include "bag_formats.hpp"

#include <algorithm>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <new>
#include <set>
#include <stdexcept>
#include <utility>

#include <ros/exception.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/query.h>
#include <rosbag/view.h>

#include "ros1_time.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::ros::ros1 {
namespace {

constexpr const char* kMagic = "#ROSBAG V2.0\n";
constexpr std::size_t kMagicSize = 13;
// Record opcodes of format 2.0.
constexpr std::uint8_t kOpMessageData = 0x02, kOpIndexData = 0x04, kOpBagHeader = 0x03,
                       kOpChunk = 0x05, kOpChunkInfo = 0x06, kOpConnection = 0x07;
constexpr std::uint32_t kIndexEntryBytes = 12;  // time sec, time nsec, offset in the chunk

// ------------------------------------------------------------------- the structural check

/// \brief One record's header as rosbag_storage reads it: its fields and where its data is.
struct RecordHeader {
  std::uint64_t pos = 0;  ///< where the record starts
  std::map<std::string, std::string> fields;
  std::uint8_t op = 0;
  std::uint64_t data_pos = 0;
  std::uint32_t data_len = 0;
};

/// \brief Bounds-checked reads of a bag file; every failure is a FormatError naming the file.
class BagFile {
 public:
  explicit BagFile(const std::string& path) : path_(path), in_(path, std::ios::binary) {
    if (!in_) throw IoError(path + ": cannot open");
    std::error_code ec;
    size_ = std::filesystem::file_size(path, ec);
    if (ec) throw IoError(path + ": cannot read its size (" + ec.message() + ")");
  }

  [[nodiscard]] std::uint64_t size() const noexcept { return size_; }

  [[noreturn]] void fail(const std::string& what) const { throw FormatError(path_, 0, what); }

  /// \brief Reads n bytes at pos; a range past the end of the file means a truncated bag.
  void read(std::uint64_t pos, void* out, std::uint64_t n, const std::string& what) {
    if (pos > size_ || n > size_ - pos) {
      fail("truncated or corrupt: " + what + " (bytes " + std::to_string(pos) + ".." +
           std::to_string(pos + n) + ") runs past the end of the file (" + std::to_string(size_) +
           " bytes)");
    }
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(pos));
    in_.read(static_cast<char*>(out), static_cast<std::streamsize>(n));
    if (!in_) fail("cannot read " + what + " at byte " + std::to_string(pos));
  }

  std::uint32_t read_u32(std::uint64_t pos, const std::string& what) {
    unsigned char b[4];
    read(pos, b, 4, what);
    return static_cast<std::uint32_t>(b[0]) | static_cast<std::uint32_t>(b[1]) << 8U |
           static_cast<std::uint32_t>(b[2]) << 16U | static_cast<std::uint32_t>(b[3]) << 24U;
  }

  /// \brief The name=value fields of a header (each prefixed by its 32-bit length), checked the
  /// way ros::Header::parse, which rosbag_storage calls, does not: every length inside the bytes.
  std::map<std::string, std::string> parse_fields(const std::string& bytes,
                                                  const std::string& what) const {
    std::map<std::string, std::string> fields;
    for (std::size_t at = 0; at < bytes.size();) {
      if (bytes.size() - at < 4) fail("corrupt: " + what + " is cut inside a field");
      std::uint32_t len = 0;
      for (int i = 3; i >= 0; --i) {
        len = len << 8U | static_cast<unsigned char>(bytes[at + static_cast<std::size_t>(i)]);
      }
      at += 4;
      if (len > bytes.size() - at) fail("corrupt: " + what + " has a field running past its end");
      const std::string field = bytes.substr(at, len);
      at += len;
      const std::string::size_type eq = field.find('=');
      if (eq == std::string::npos) fail("corrupt: " + what + " has a field without '='");
      fields[field.substr(0, eq)] = field.substr(eq + 1);
    }
    return fields;
  }

  /// \brief Reads the record header at pos (header length, name=value fields, data length).
  RecordHeader record(std::uint64_t pos, const std::string& what) {
    RecordHeader r;
    r.pos = pos;
    const std::uint32_t header_len = read_u32(pos, what + " header length");
    if (header_len > size_ - pos - 4) {
      fail("truncated or corrupt: " + where(r, what) + " declares a header of " +
           std::to_string(header_len) + " bytes, past the end of the file (" +
           std::to_string(size_) + " bytes)");
    }
    std::string header(header_len, '\0');
    read(pos + 4, header.data(), header_len, what + " header");
    r.fields = parse_fields(header, where(r, what) + ": its header");
    const std::string op = field(r, "op", 1, what);
    r.op = static_cast<std::uint8_t>(op[0]);
    r.data_len = read_u32(pos + 4 + header_len, what + " data length");
    r.data_pos = pos + 8 + header_len;
    if (r.data_len > size_ - r.data_pos) {
      fail("truncated or corrupt: " + where(r, what) + " declares " + std::to_string(r.data_len) +
           " data bytes, past the end of the file (" + std::to_string(size_) + " bytes)");
    }
    return r;
  }

  /// \brief The record's field `name`, required, of exactly `bytes` bytes (0: any length).
  std::string field(const RecordHeader& r, const std::string& name, std::size_t bytes,
                    const std::string& what) const {
    const auto it = r.fields.find(name);
    if (it == r.fields.end())
      fail("corrupt: " + where(r, what) + ": its header has no '" + name + "' field");
    if (bytes > 0 && it->second.size() != bytes) {
      fail(where(r, what) + ": its '" + name + "' field has " + std::to_string(it->second.size()) +
           " bytes, not " + std::to_string(bytes));
    }
    return it->second;
  }

  std::uint64_t field_uint(const RecordHeader& r, const std::string& name, std::size_t bytes,
                           const std::string& what) const {
    const std::string v = field(r, name, bytes, what);
    std::uint64_t x = 0;
    for (std::size_t i = v.size(); i-- > 0;) x = x << 8U | static_cast<unsigned char>(v[i]);
    return x;
  }

  void expect_op(const RecordHeader& r, std::uint8_t op, const std::string& what) const {
    if (r.op != op) {
      fail("corrupt: " + where(r, what) + " has op " + std::to_string(r.op) + ", expected " +
           std::to_string(op));
    }
  }

  static std::string where(const RecordHeader& r, const std::string& what) {
    return what + " at byte " + std::to_string(r.pos);
  }

 private:
  std::string path_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
};

/// \brief What the check learnt that the reader uses: the largest uncompressed chunk.
struct BagCheck {
  std::uint64_t max_chunk_bytes = 0;
};

/// \brief The first line of a ROS bag ("#ROSBAG V2.0"); refuses every other version.
void check_version(BagFile& f, const std::string& path) {
  char head[64] = {};
  const std::uint64_t n = std::min<std::uint64_t>(sizeof(head), f.size());
  f.read(0, head, n, "the version line");
  const std::string text(head, static_cast<std::size_t>(n));
  if (text.compare(0, kMagicSize, kMagic) == 0) return;
  if (text.size() < kMagicSize && std::string(kMagic).compare(0, text.size(), text) == 0) {
    f.fail("truncated: the file ends inside the version line '#ROSBAG V2.0' (" +
           std::to_string(text.size()) + " bytes)");
  }
  const std::string line = text.substr(0, text.find('\n'));
  std::string version = "unknown";
  if (const std::string::size_type v = line.find(" V");
      line.rfind("#ROS", 0) == 0 && v != std::string::npos) {
    version = line.substr(v + 2);
  }
  throw FormatError(path, 0,
                    "only ROS bag format 2.0 ('#ROSBAG V2.0') is read; this file is format " +
                        version + " ('" + line.substr(0, 40) +
                        "'); `rosbag fix` converts older bags");
}

/// \brief Checks the message record an index entry points to in an uncompressed chunk the way
/// rosbag_storage reads it (connection records before it skipped), so that every header and data
/// length it will follow stays inside the chunk. Compressed chunks are checked by their
/// decompressors instead (bz2 and lz4 carry checksums; an error there is an exception).
void check_message_record(BagFile& f, const RecordHeader& chunk, std::uint32_t offset) {
  const std::uint64_t end = chunk.data_pos + chunk.data_len;
  for (std::uint64_t pos = chunk.data_pos + offset;;) {
    const std::string what = "the record at offset " + std::to_string(pos - chunk.data_pos) +
                             " of the chunk at byte " + std::to_string(chunk.pos);
    if (pos + 8 > end) f.fail("corrupt index: " + what + " is past the end of its chunk");
    const RecordHeader r = f.record(pos, what);
    if (r.data_pos + r.data_len > end) {
      f.fail("corrupt: " + what + " runs past the end of its chunk");
    }
    if (r.op == kOpMessageData) return;
    if (r.op != kOpConnection) {
      f.fail("corrupt index: " + what + " has op " + std::to_string(r.op) +
             ", not a message (2) or connection (7)");
    }
    pos = r.data_pos + r.data_len;
  }
}

/// \brief Walks what rosbag_storage reads when it opens a 2.0 bag (bag header, connection and
/// chunk info records at the index position, each chunk's header and the index records that
/// follow it) and checks every length, position, count and name against the file.
BagCheck check_structure(const std::string& path) {
  BagFile f(path);
  check_version(f, path);
  BagCheck out;

  const RecordHeader bag_header = f.record(kMagicSize, "the bag header record");
  f.expect_op(bag_header, kOpBagHeader, "the bag header record");
  if (bag_header.fields.count("encryptor") > 0) {
    f.fail("the bag is encrypted (encryptor '" + bag_header.fields.at("encryptor") +
           "'): encrypted bags are not read");
  }
  const std::uint64_t index_pos = f.field_uint(bag_header, "index_pos", 8, "the bag header");
  const auto conn_count = f.field_uint(bag_header, "conn_count", 4, "the bag header");
  const auto chunk_count = f.field_uint(bag_header, "chunk_count", 4, "the bag header");
  if (index_pos == 0) {
    f.fail("the bag has no index (its recording was cut short?); `rosbag reindex` writes one");
  }
  if (index_pos >= f.size()) {
    f.fail("truncated: the index starts at byte " + std::to_string(index_pos) +
           ", past the end of the file (" + std::to_string(f.size()) + " bytes)");
  }
  const std::uint64_t chunks_begin = bag_header.data_pos + bag_header.data_len;
  if (index_pos < chunks_begin) {
    f.fail("corrupt: the index position " + std::to_string(index_pos) +
           " is inside the bag header record");
  }

  // Connection records, then chunk info records, at index_pos.
  std::set<std::uint32_t> connections;
  std::uint64_t pos = index_pos;
  for (std::uint64_t i = 0; i < conn_count; ++i) {
    const RecordHeader r = f.record(pos, "connection record " + std::to_string(i));
    f.expect_op(r, kOpConnection, "connection record " + std::to_string(i));
    connections.insert(static_cast<std::uint32_t>(f.field_uint(r, "conn", 4, "connection")));
    (void)f.field(r, "topic", 0, "connection record");
    // Its data is the connection header (topic, type, md5sum, message_definition), which
    // rosbag_storage parses as a header too.
    std::string data(r.data_len, '\0');
    f.read(r.data_pos, data.data(), r.data_len, "connection record data");
    const auto conn_fields =
        f.parse_fields(data, BagFile::where(r, "connection record " + std::to_string(i)) +
                                 ": its connection header");
    if (conn_fields.count("type") == 0) {
      f.fail("corrupt: " + BagFile::where(r, "connection record " + std::to_string(i)) +
             ": its connection header has no 'type'");
    }
    pos = r.data_pos + r.data_len;
  }
  struct ChunkInfo {
    std::uint64_t pos = 0;
    std::size_t connections = 0;
  };
  std::vector<ChunkInfo> chunks;
  for (std::uint64_t i = 0; i < chunk_count; ++i) {
    const std::string what = "chunk info record " + std::to_string(i);
    const RecordHeader r = f.record(pos, what);
    f.expect_op(r, kOpChunkInfo, what);
    if (f.field_uint(r, "ver", 4, what) != 1) f.fail(BagFile::where(r, what) + ": version not 1");
    (void)f.field(r, "start_time", 8, what);
    (void)f.field(r, "end_time", 8, what);
    const std::uint64_t count = f.field_uint(r, "count", 4, what);
    if (count * 8 > r.data_len) {
      f.fail("corrupt: " + BagFile::where(r, what) + " lists " + std::to_string(count) +
             " connections in " + std::to_string(r.data_len) + " bytes");
    }
    std::set<std::uint32_t> in_chunk;
    for (std::uint64_t k = 0; k < count; ++k) {
      const std::uint32_t conn = f.read_u32(r.data_pos + 8 * k, what);
      if (connections.count(conn) == 0) {
        f.fail("corrupt: " + BagFile::where(r, what) + " names connection " + std::to_string(conn) +
               ", which has no connection record");
      }
      in_chunk.insert(conn);  // rosbag_storage keeps them in a map: duplicates count once
    }
    ChunkInfo c;
    c.pos = f.field_uint(r, "chunk_pos", 8, what);
    c.connections = in_chunk.size();
    if (c.pos < chunks_begin || c.pos >= index_pos) {
      f.fail("corrupt: " + BagFile::where(r, what) + " places its chunk at byte " +
             std::to_string(c.pos) + ", outside the chunks (bytes " + std::to_string(chunks_begin) +
             ".." + std::to_string(index_pos) + ")");
    }
    chunks.push_back(c);
    pos = r.data_pos + r.data_len;
  }

  // Each chunk's header, then one index data record per connection of the chunk. rosbag_storage
  // reads an index record's entries by its count and goes on right after them, whatever data
  // length the record declares (some old writers declared more: scan_tools' demo.bag), so the
  // walk does the same.
  for (const ChunkInfo& c : chunks) {
    const std::string what = "the chunk";
    const RecordHeader chunk = f.record(c.pos, what);
    f.expect_op(chunk, kOpChunk, what);
    const std::string compression = f.field(chunk, "compression", 0, what);
    if (compression != "none" && compression != "bz2" && compression != "lz4") {
      f.fail("unknown chunk compression '" + compression + "' in " + BagFile::where(chunk, what) +
             " (a ROS 1 bag's chunks are none, bz2 or lz4)");
    }
    const std::uint64_t chunk_bytes = f.field_uint(chunk, "size", 4, what);
    if (compression == "none" && chunk_bytes != chunk.data_len) {
      f.fail("corrupt: " + BagFile::where(chunk, what) + " is uncompressed with " +
             std::to_string(chunk.data_len) + " bytes but says it holds " +
             std::to_string(chunk_bytes));
    }
    out.max_chunk_bytes = std::max(out.max_chunk_bytes, chunk_bytes);
    pos = chunk.data_pos + chunk.data_len;
    for (std::size_t k = 0; k < c.connections; ++k) {
      const std::string iwhat =
          "index record " + std::to_string(k) + " of the chunk at byte " + std::to_string(c.pos);
      const RecordHeader r = f.record(pos, iwhat);
      f.expect_op(r, kOpIndexData, iwhat);
      if (f.field_uint(r, "ver", 4, iwhat) != 1) {
        f.fail(BagFile::where(r, iwhat) + ": version not 1");
      }
      const auto conn = static_cast<std::uint32_t>(f.field_uint(r, "conn", 4, iwhat));
      if (connections.count(conn) == 0) {
        f.fail("corrupt: " + BagFile::where(r, iwhat) + " names connection " +
               std::to_string(conn) + ", which has no connection record");
      }
      const std::uint64_t count = f.field_uint(r, "count", 4, iwhat);
      const std::uint64_t entries_bytes = count * kIndexEntryBytes;
      if (entries_bytes > r.data_len) {
        f.fail("corrupt: " + BagFile::where(r, iwhat) + " has " + std::to_string(count) +
               " entries but only " + std::to_string(r.data_len) + " data bytes");
      }
      std::vector<unsigned char> entries(static_cast<std::size_t>(entries_bytes));
      f.read(r.data_pos, entries.data(), entries_bytes, iwhat);
      for (std::uint64_t e = 0; e < count; ++e) {
        const unsigned char* b = entries.data() + e * kIndexEntryBytes + 8;
        const std::uint32_t offset =
            static_cast<std::uint32_t>(b[0]) | static_cast<std::uint32_t>(b[1]) << 8U |
            static_cast<std::uint32_t>(b[2]) << 16U | static_cast<std::uint32_t>(b[3]) << 24U;
        // The smallest record: header length, an empty header, data length.
        if (static_cast<std::uint64_t>(offset) + 8 > chunk_bytes) {
          f.fail("corrupt index: " + BagFile::where(r, iwhat) + " places message " +
                 std::to_string(e) + " at offset " + std::to_string(offset) +
                 ", past the end of its chunk (" + std::to_string(chunk_bytes) + " bytes)");
        }
        if (compression == "none") check_message_record(f, chunk, offset);
      }
      pos = r.data_pos + entries_bytes;
    }
  }
  return out;
}

// --------------------------------------------------------------------------- the reader

/// \brief Rethrows the exception being handled as a vdtnav exception: vdtnav's as they are,
/// anything rosbag_storage (or what it uses) throws as FormatError naming the file.
[[noreturn]] void rethrow_as_vdtnav(const std::string& path, const std::string& doing) {
  try {
    throw;
  } catch (const vdtnav::Error&) {
    throw;
  } catch (const rosbag::BagUnindexedException&) {
    throw FormatError(path, 0, "the bag has no index; `rosbag reindex` writes one");
  } catch (const std::bad_alloc&) {
    throw FormatError(path, 0, doing + ": a length in the file is too large (corrupt bag?)");
  } catch (const std::exception& e) {
    throw FormatError(path, 0, doing + ": " + e.what());
  } catch (...) {
    throw FormatError(path, 0, doing + ": unknown error");
  }
}

/// \brief A ROS 1 bag opened with rosbag_storage after check_structure() passed.
class Ros1Bag final : public BagReader {
 public:
  explicit Ros1Bag(const std::string& path) : path_(path) {
    check_ = check_structure(path);
    try {
      bag_.open(path, rosbag::bagmode::Read);
      if (bag_.getMajorVersion() != 2 || bag_.getMinorVersion() != 0) {
        throw FormatError(path, 0,
                          "only ROS bag format 2.0 is read; this file is format " +
                              std::to_string(bag_.getMajorVersion()) + "." +
                              std::to_string(bag_.getMinorVersion()));
      }
      // Topics from the index alone (a MessageInstance's topic, type and time come from the
      // index and its connection; no chunk is read). Connections of one topic are merged.
      std::map<std::string, BagTopic> by_name;
      rosbag::View view(bag_);
      for (const rosbag::MessageInstance& m : view) {
        const std::int64_t t = detail::to_ns(m.getTime().sec, m.getTime().nsec);
        BagTopic& topic = by_name[m.getTopic()];
        if (topic.count == 0) {
          topic.name = m.getTopic();
          topic.type = m.getDataType();
          topic.first_ns = topic.last_ns = t;
        }
        ++topic.count;
        topic.first_ns = std::min(topic.first_ns, t);
        topic.last_ns = std::max(topic.last_ns, t);
      }
      for (auto& entry : by_name) topics_.push_back(std::move(entry.second));
    } catch (...) {
      rethrow_as_vdtnav(path_, "opening the bag");
    }
  }

  [[nodiscard]] BagFormat format() const noexcept override { return BagFormat::kRos1; }
  [[nodiscard]] const std::string& path() const noexcept override { return path_; }
  [[nodiscard]] const std::vector<BagTopic>& topics() const noexcept override { return topics_; }

  [[nodiscard]] std::uint64_t size_bytes() const override {
    std::error_code ec;
    const std::uintmax_t n = std::filesystem::file_size(path_, ec);
    if (ec) throw IoError(path_ + ": cannot read its size (" + ec.message() + ")");
    return static_cast<std::uint64_t>(n);
  }

  void read(const std::vector<std::string>& topics,
            const std::function<bool(const BagMessage&)>& visit) const override {
    // rosbag_storage's reads are const but share the bag's chunk buffer: one read at a time.
    std::unique_ptr<rosbag::View> view;
    rosbag::View::iterator it, end;
    try {
      view = topics.empty() ? std::make_unique<rosbag::View>(bag_)
                            : std::make_unique<rosbag::View>(bag_, rosbag::TopicQuery(topics));
      it = view->begin();
      end = view->end();
    } catch (...) {
      rethrow_as_vdtnav(path_, "reading the index");
    }
    BagMessage msg;
    msg.format = BagFormat::kRos1;
    while (true) {
      try {
        if (it == end) return;
        const rosbag::MessageInstance& m = *it;
        msg.topic = m.getTopic();
        msg.type = m.getDataType();
        msg.recorded_ns = detail::to_ns(m.getTime().sec, m.getTime().nsec);
        const std::uint32_t n = m.size();
        if (n > check_.max_chunk_bytes) {
          throw FormatError(path_, 0,
                            "corrupt: a message of " + msg.topic + " declares " +
                                std::to_string(n) + " bytes, more than its chunk holds");
        }
        msg.data.resize(n);
        ::ros::serialization::OStream stream(msg.data.data(), n);
        m.write(stream);
      } catch (...) {
        rethrow_as_vdtnav(path_, "reading a message");
      }
      if (!visit(msg)) return;  // outside the try: the visitor's exceptions pass unchanged
      try {
        ++it;
      } catch (...) {
        rethrow_as_vdtnav(path_, "reading the index");
      }
    }
  }

 private:
  std::string path_;
  BagCheck check_;
  rosbag::Bag bag_;
  std::vector<BagTopic> topics_;
};

}  // namespace

std::unique_ptr<BagReader> open(const std::string& path) { return std::make_unique<Ros1Bag>(path); }

}  // namespace vdtnav::ros::ros1
