// ROS 2 bags (rosbag2): a folder with metadata.yaml (rosbag2_bagfile_information) and sqlite3
// .db3 files whose `topics` table names the topics and whose `messages` table holds
// (topic_id, timestamp ns, CDR data). Read with the sqlite3 C API, files merged by timestamp.
// The CDR decoders are in ros2_cdr.cpp.

#include <sqlite3.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bag_formats.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::ros::ros2 {
namespace {

namespace fs = std::filesystem;

const char* const kMcapHint =
    "mcap storage is not read: convert the bag to sqlite3 with `ros2 bag convert -i BAG -o "
    "out.yaml` where out.yaml sets storage_id: sqlite3";

// ---- sqlite3 RAII -------------------------------------------------------------------------------

struct DbClose {
  void operator()(sqlite3* db) const noexcept { sqlite3_close_v2(db); }
};
struct StmtFinalize {
  void operator()(sqlite3_stmt* s) const noexcept { sqlite3_finalize(s); }
};
using DbPtr = std::unique_ptr<sqlite3, DbClose>;
using StmtPtr = std::unique_ptr<sqlite3_stmt, StmtFinalize>;

/// Throws FormatError for file with sqlite's message for db (or rc when db has none).
[[noreturn]] void throw_sqlite(const std::string& file, sqlite3* db, int rc,
                               const std::string& doing) {
  const std::string msg = db != nullptr ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
  throw FormatError(file, 0,
                    "expected a rosbag2 sqlite3 database; sqlite failed " + doing + ": " + msg);
}

StmtPtr prepare(sqlite3* db, const std::string& file, const std::string& sql) {
  sqlite3_stmt* raw = nullptr;
  const int rc = sqlite3_prepare_v2(db, sql.c_str(), static_cast<int>(sql.size()), &raw, nullptr);
  StmtPtr stmt(raw);
  if (rc != SQLITE_OK) throw_sqlite(file, db, rc, "to prepare `" + sql + "`");
  return stmt;
}

/// Steps stmt: true for a row, false when done, FormatError otherwise.
bool step(sqlite3_stmt* stmt, const std::string& file) {
  const int rc = sqlite3_step(stmt);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  throw_sqlite(file, sqlite3_db_handle(stmt), rc, "to read");
}

std::string column_text(sqlite3_stmt* stmt, int col) {
  const unsigned char* t = sqlite3_column_text(stmt, col);
  return t == nullptr ? std::string() : std::string(reinterpret_cast<const char*>(t));
}

/// A file URI for sqlite3_open_v2 (RFC 3986: '%', '?' and '#' must be escaped).
std::string file_uri(const fs::path& p) {
  std::string uri = "file:";
  for (const char c : fs::absolute(p).string()) {
    if (c == '%' || c == '?' || c == '#') {
      static const char* const kHex = "0123456789ABCDEF";
      const auto u = static_cast<unsigned char>(c);
      uri += '%';
      uri += kHex[u >> 4];
      uri += kHex[u & 0xF];
    } else {
      uri += c;
    }
  }
  return uri;
}

std::uint32_t read_be32(const unsigned char* b) {
  return (std::uint32_t{b[0]} << 24) | (std::uint32_t{b[1]} << 16) | (std::uint32_t{b[2]} << 8) |
         std::uint32_t{b[3]};
}

/// Checks the file is a whole sqlite3 database before sqlite opens it, for a clear message: the
/// 100-byte header starts "SQLite format 3\0"; the page size is at offset 16 (big-endian, 1 means
/// 65536) and, when the "version-valid-for" number (offset 92) equals the change counter
/// (offset 24), the database size in pages at offset 28 is valid (sqlite's file format, 1.3).
void check_sqlite_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw IoError(p.string() + ": cannot open");
  std::array<unsigned char, 100> h{};
  in.read(reinterpret_cast<char*>(h.data()), static_cast<std::streamsize>(h.size()));
  static const char kMagic[] = "SQLite format 3";  // 16 bytes with its NUL
  if (in.gcount() != static_cast<std::streamsize>(h.size()) ||
      !std::equal(kMagic, kMagic + sizeof(kMagic), h.begin())) {
    throw FormatError(p.string(), 0,
                      "not a sqlite3 database: expected a rosbag2 .db3 file starting with "
                      "'SQLite format 3'");
  }
  const std::uint32_t raw_page = (std::uint32_t{h[16]} << 8) | h[17];
  const std::uint64_t page_size = raw_page == 1 ? 65536 : raw_page;
  const std::uint32_t pages = read_be32(&h[28]);
  if (pages > 0 && read_be32(&h[92]) == read_be32(&h[24])) {
    std::error_code ec;
    const std::uintmax_t have = fs::file_size(p, ec);
    const std::uint64_t want = page_size * pages;
    if (!ec && have < want) {
      throw FormatError(p.string(), 0,
                        "truncated sqlite3 database: its header says " + std::to_string(want) +
                            " bytes, the file has " + std::to_string(have));
    }
  }
}

// ---- metadata.yaml
// -------------------------------------------------------------------------------

struct TopicMeta {
  std::string name, type, serialization_format;
};

struct Metadata {
  std::string storage_identifier;
  std::vector<std::string> relative_file_paths;
  std::vector<TopicMeta> topics;
};

std::size_t line_of(const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  return m.line >= 0 ? static_cast<std::size_t>(m.line) + 1 : 0;
}

std::string scalar(const YAML::Node& parent, const char* key, const std::string& file,
                   bool required) {
  const YAML::Node n = parent[key];
  if (!n) {
    if (!required) return {};
    throw FormatError(file, line_of(parent), std::string("expected the key '") + key + "'");
  }
  if (n.IsNull()) return {};
  if (!n.IsScalar()) {
    throw FormatError(file, line_of(n), std::string("expected '") + key + "' to be a scalar");
  }
  return n.Scalar();
}

/// Reads rosbag2's metadata.yaml (rosbag2_storage/bag_metadata.hpp, versions 1 to 8).
Metadata read_metadata(const fs::path& yaml_path) {
  const std::string file = yaml_path.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    throw IoError(file + ": cannot open");
  } catch (const YAML::Exception& e) {
    throw FormatError(file, e.mark.line >= 0 ? static_cast<std::size_t>(e.mark.line) + 1 : 0,
                      "expected YAML: " + e.msg);
  }
  const YAML::Node info = root["rosbag2_bagfile_information"];
  if (!info || !info.IsMap()) {
    throw FormatError(file, 0, "expected a map 'rosbag2_bagfile_information' (rosbag2 metadata)");
  }
  Metadata md;
  try {
    md.storage_identifier = scalar(info, "storage_identifier", file, true);
    if (md.storage_identifier == "mcap") {
      throw FormatError(file, line_of(info["storage_identifier"]), kMcapHint);
    }
    if (md.storage_identifier != "sqlite3") {
      throw FormatError(
          file, line_of(info["storage_identifier"]),
          "expected storage_identifier sqlite3, found '" + md.storage_identifier + "'");
    }
    const std::string compression = scalar(info, "compression_format", file, false);
    if (!compression.empty()) {
      throw FormatError(file, line_of(info["compression_format"]),
                        "compressed bags (compression_format '" + compression + "', mode '" +
                            scalar(info, "compression_mode", file, false) +
                            "') are not read: expected compression_format \"\"; decompress "
                            "the bag with `ros2 bag decompress` (or `ros2 bag convert`)");
    }
    const YAML::Node files = info["relative_file_paths"];
    if (!files || !files.IsSequence() || files.size() == 0) {
      throw FormatError(file, line_of(files ? files : info),
                        "expected a non-empty sequence 'relative_file_paths'");
    }
    for (const YAML::Node& f : files) {
      if (!f.IsScalar()) {
        throw FormatError(file, line_of(f), "expected a file name in relative_file_paths");
      }
      const std::string name = f.Scalar();
      if (fs::path(name).extension() == ".mcap") throw FormatError(file, line_of(f), kMcapHint);
      md.relative_file_paths.push_back(name);
    }
    const YAML::Node topics = info["topics_with_message_count"];
    if (topics && !topics.IsNull()) {
      if (!topics.IsSequence()) {
        throw FormatError(file, line_of(topics), "expected a sequence 'topics_with_message_count'");
      }
      for (const YAML::Node& t : topics) {
        const YAML::Node tm = t["topic_metadata"];
        if (!tm || !tm.IsMap()) {
          throw FormatError(file, line_of(t), "expected 'topic_metadata' with name and type");
        }
        TopicMeta m{scalar(tm, "name", file, true), scalar(tm, "type", file, true),
                    scalar(tm, "serialization_format", file, true)};
        if (m.serialization_format != "cdr") {
          throw FormatError(file, line_of(tm["serialization_format"]),
                            "topic " + m.name + ": expected serialization_format cdr, found '" +
                                m.serialization_format + "'");
        }
        md.topics.push_back(std::move(m));
      }
    }
  } catch (const YAML::Exception& e) {
    throw FormatError(file, e.mark.line >= 0 ? static_cast<std::size_t>(e.mark.line) + 1 : 0,
                      "expected rosbag2 metadata: " + e.msg);
  }
  return md;
}

// ---- the bag
// -------------------------------------------------------------------------------------

/// One .db3 file: its connection and its topic ids -> index into Ros2Bag::topics_.
struct DbFile {
  fs::path path;
  DbPtr db;
  std::map<std::int64_t, std::size_t> topic_of_id;
};

class Ros2Bag final : public BagReader {
 public:
  explicit Ros2Bag(std::string path) : path_(std::move(path)) {
    const fs::path given(path_);
    std::error_code ec;
    const bool is_dir = fs::is_directory(given, ec);
    if (!is_dir && given.extension() == ".mcap") throw FormatError(path_, 0, kMcapHint);
    folder_ = is_dir ? given : given.parent_path();
    if (folder_.empty()) folder_ = ".";
    const fs::path yaml = folder_ / "metadata.yaml";

    std::vector<fs::path> files;
    Metadata md;
    if (fs::exists(yaml, ec)) {
      md = read_metadata(yaml);
      extra_files_.push_back(yaml);
      for (const std::string& rel : md.relative_file_paths) {
        fs::path f = folder_ / rel;
        // rosbag2 before metadata version 4 wrote the paths relative to the bag's parent folder.
        if (!fs::exists(f, ec) && fs::exists(folder_.parent_path() / rel, ec)) {
          f = folder_.parent_path() / rel;
        }
        if (!fs::exists(f, ec)) {
          throw FormatError(
              yaml.string(), 0,
              "relative_file_paths names " + rel + ", but " + f.string() + " does not exist");
        }
        files.push_back(f);
      }
    } else {
      files = find_storage_files();
    }
    for (const fs::path& f : files) open_db(f);
    for (const TopicMeta& t : md.topics) topic_index(t.name, t.type, yaml.string());
    count_messages();
    std::vector<std::size_t> order(topics_.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return topics_[a].name < topics_[b].name; });
    std::vector<std::size_t> new_index(order.size());
    std::vector<BagTopic> sorted;
    for (std::size_t i = 0; i < order.size(); ++i) {
      new_index[order[i]] = i;
      sorted.push_back(std::move(topics_[order[i]]));
    }
    topics_ = std::move(sorted);
    for (DbFile& f : files_) {
      for (auto& [id, index] : f.topic_of_id) index = new_index[index];
    }
  }

  [[nodiscard]] BagFormat format() const noexcept override { return BagFormat::kRos2; }
  [[nodiscard]] const std::string& path() const noexcept override { return path_; }
  [[nodiscard]] const std::vector<BagTopic>& topics() const noexcept override { return topics_; }

  [[nodiscard]] std::uint64_t size_bytes() const override {
    std::uint64_t total = 0;
    auto add = [&](const fs::path& p) {
      std::error_code ec;
      const std::uintmax_t s = fs::file_size(p, ec);
      if (ec) throw IoError(p.string() + ": cannot read its size: " + ec.message());
      total += s;
    };
    for (const DbFile& f : files_) add(f.path);
    for (const fs::path& p : extra_files_) add(p);
    return total;
  }

  void read(const std::vector<std::string>& topics,
            const std::function<bool(const BagMessage&)>& visit) const override {
    // One cursor per file, each in timestamp order (the rosbag2 schema indexes messages by
    // timestamp); the files are merged by timestamp, ties in file order.
    struct Cursor {
      const DbFile* file;
      StmtPtr stmt;
      bool has_row;
    };
    std::vector<Cursor> cursors;
    for (const DbFile& f : files_) {
      std::vector<std::int64_t> ids;
      for (const auto& [id, index] : f.topic_of_id) {
        if (topics.empty() ||
            std::find(topics.begin(), topics.end(), topics_[index].name) != topics.end()) {
          ids.push_back(id);
        }
      }
      if (ids.empty()) continue;
      std::string sql = "SELECT topic_id, timestamp, data FROM messages";
      if (!topics.empty()) {
        sql += " WHERE topic_id IN (";
        for (std::size_t i = 0; i < ids.size(); ++i) sql += i == 0 ? "?" : ",?";
        sql += ")";
      }
      sql += " ORDER BY timestamp, id";
      const std::string file = f.path.string();
      StmtPtr stmt = prepare(f.db.get(), file, sql);
      if (!topics.empty()) {
        for (std::size_t i = 0; i < ids.size(); ++i) {
          const int rc = sqlite3_bind_int64(stmt.get(), static_cast<int>(i) + 1, ids[i]);
          if (rc != SQLITE_OK) throw_sqlite(file, f.db.get(), rc, "to bind a topic id");
        }
      }
      const bool has_row = step(stmt.get(), file);
      cursors.push_back(Cursor{&f, std::move(stmt), has_row});
    }

    BagMessage m;
    m.format = BagFormat::kRos2;
    for (;;) {
      Cursor* next = nullptr;
      for (Cursor& c : cursors) {
        if (c.has_row && (next == nullptr || sqlite3_column_int64(c.stmt.get(), 1) <
                                                 sqlite3_column_int64(next->stmt.get(), 1))) {
          next = &c;
        }
      }
      if (next == nullptr) return;
      sqlite3_stmt* s = next->stmt.get();
      const auto it = next->file->topic_of_id.find(sqlite3_column_int64(s, 0));
      if (it == next->file->topic_of_id.end()) {
        throw FormatError(next->file->path.string(), 0,
                          "a message names topic_id " + std::to_string(sqlite3_column_int64(s, 0)) +
                              ", which the topics table does not have");
      }
      const BagTopic& topic = topics_[it->second];
      m.topic = topic.name;
      m.type = topic.type;
      m.recorded_ns = sqlite3_column_int64(s, 1);
      const auto* blob = static_cast<const std::uint8_t*>(sqlite3_column_blob(s, 2));
      const int bytes = sqlite3_column_bytes(s, 2);
      if (blob == nullptr || bytes <= 0) {
        m.data.clear();
      } else {
        m.data.assign(blob, blob + bytes);
      }
      if (!visit(m)) return;
      next->has_row = step(s, next->file->path.string());
    }
  }

 private:
  /// Without metadata.yaml: the folder's .db3 files in name order (rosbag2 names them
  /// <bag>_0.db3, <bag>_1.db3, ...; fewer than 10 files sort right by name).
  std::vector<fs::path> find_storage_files() const {
    std::vector<fs::path> db3, mcap;
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(folder_, ec)) {
      if (e.path().extension() == ".db3") db3.push_back(e.path());
      if (e.path().extension() == ".mcap") mcap.push_back(e.path());
    }
    if (ec) throw IoError(folder_.string() + ": cannot list: " + ec.message());
    if (db3.empty() && !mcap.empty()) throw FormatError(mcap.front().string(), 0, kMcapHint);
    if (db3.empty()) {
      throw FormatError(path_, 0,
                        "not a ROS 2 bag: expected a folder with metadata.yaml and sqlite3 .db3 "
                        "files");
    }
    std::sort(db3.begin(), db3.end(), [](const fs::path& a, const fs::path& b) {
      const std::string sa = a.filename().string(), sb = b.filename().string();
      return sa.size() != sb.size() ? sa.size() < sb.size() : sa < sb;
    });
    return db3;
  }

  /// The index of topic name in topics_, added when new; FormatError when a type disagrees.
  std::size_t topic_index(const std::string& name, const std::string& type,
                          const std::string& where) {
    for (std::size_t i = 0; i < topics_.size(); ++i) {
      if (topics_[i].name != name) continue;
      if (topics_[i].type != type) {
        throw FormatError(where, 0,
                          "topic " + name + " has type " + type + " here and " + topics_[i].type +
                              " elsewhere in the bag");
      }
      return i;
    }
    BagTopic t;
    t.name = name;
    t.type = type;
    topics_.push_back(std::move(t));
    return topics_.size() - 1;
  }

  void open_db(const fs::path& p) {
    const std::string file = p.string();
    if (p.extension() == ".mcap") throw FormatError(file, 0, kMcapHint);
    check_sqlite_file(p);
    // Read-only, and immutable unless a write-ahead log is beside the file: a finished bag is not
    // written to, and sqlite then creates no -shm/-wal files (bags often lie in read-only
    // folders). A non-empty -wal (a recording not checkpointed) is read through normal locking.
    std::error_code ec;
    const fs::path wal(file + "-wal");
    const bool has_wal = fs::exists(wal, ec) && fs::file_size(wal, ec) > 0;
    const std::string uri = file_uri(p) + (has_wal ? "?mode=ro" : "?mode=ro&immutable=1");
    sqlite3* raw = nullptr;
    const int rc =
        sqlite3_open_v2(uri.c_str(), &raw, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr);
    DbFile f{p, DbPtr(raw), {}};
    if (rc != SQLITE_OK) throw_sqlite(file, raw, rc, "to open");

    StmtPtr stmt = prepare(f.db.get(), file,
                           "SELECT id, name, type, serialization_format FROM topics ORDER BY id");
    while (step(stmt.get(), file)) {
      const std::string name = column_text(stmt.get(), 1);
      const std::string type = column_text(stmt.get(), 2);
      const std::string ser = column_text(stmt.get(), 3);
      if (ser != "cdr") {
        throw FormatError(
            file, 0, "topic " + name + ": expected serialization_format cdr, found '" + ser + "'");
      }
      f.topic_of_id[sqlite3_column_int64(stmt.get(), 0)] = topic_index(name, type, file);
    }
    files_.push_back(std::move(f));
  }

  /// Counts and time spans from the databases (not metadata.yaml, which may be stale).
  void count_messages() {
    for (const DbFile& f : files_) {
      const std::string file = f.path.string();
      StmtPtr stmt = prepare(f.db.get(), file,
                             "SELECT topic_id, COUNT(*), MIN(timestamp), MAX(timestamp) FROM "
                             "messages GROUP BY topic_id");
      while (step(stmt.get(), file)) {
        const auto it = f.topic_of_id.find(sqlite3_column_int64(stmt.get(), 0));
        if (it == f.topic_of_id.end()) {
          throw FormatError(file, 0,
                            "messages name topic_id " +
                                std::to_string(sqlite3_column_int64(stmt.get(), 0)) +
                                ", which the topics table does not have");
        }
        BagTopic& t = topics_[it->second];
        const auto n = static_cast<std::size_t>(sqlite3_column_int64(stmt.get(), 1));
        const std::int64_t first = sqlite3_column_int64(stmt.get(), 2);
        const std::int64_t last = sqlite3_column_int64(stmt.get(), 3);
        t.first_ns = t.count == 0 ? first : std::min(t.first_ns, first);
        t.last_ns = t.count == 0 ? last : std::max(t.last_ns, last);
        t.count += n;
      }
    }
  }

  std::string path_;
  fs::path folder_;
  std::vector<DbFile> files_;
  std::vector<fs::path> extra_files_;  // metadata.yaml
  std::vector<BagTopic> topics_;
};

}  // namespace

std::unique_ptr<BagReader> open(const std::string& path) { return std::make_unique<Ros2Bag>(path); }

}  // namespace vdtnav::ros::ros2
