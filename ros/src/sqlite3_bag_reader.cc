// The rosbag2 sqlite3 reader (OpenRosbag2Sqlite3Bag): one .db3 file, or a bag folder whose
// metadata.yaml names its .db3 files (merged by log time, merged_bag_reader.h).
//
// Each file is opened read-only and immutable (the URI parameter `immutable=1`: no locks, no
// journal, nothing written beside the bag). The messages are streamed by one statement,
// `SELECT topic_id, timestamp, data FROM messages ORDER BY timestamp, id`: rosbag2's index
// timestamp_idx on (timestamp) (with the rowid id) serves the order without sorting; a file
// without that index is sorted by SQLite's external sorter (temporary files, bounded memory).
// One row is held at a time, so memory is SQLite's page cache plus the largest sample.
//
// Errors name the file; SQLite gives no byte offsets, so their offset is 0 and the message names
// the table and row (messages.id) that is wrong.
#include <sqlite3.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <unordered_map>
#include <utility>

#include "merged_bag_reader.h"
#include "rosbag2_metadata.h"
#include "semgraph/ros/bag_reader.h"

namespace semgraph::ros {
namespace {

constexpr std::string_view kSqliteMagic{"SQLite format 3\0", 16};

// "file:" URI of a path, with the characters that URIs reserve percent-encoded.
std::string FileUri(const std::string& path) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string uri = "file:";
  for (const char c : std::filesystem::absolute(path).string()) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '%' || c == '?' || c == '#' || u < 0x20 || u >= 0x7f) {
      uri += '%';
      uri += kHex[u >> 4];
      uri += kHex[u & 15];
    } else {
      uri += c;
    }
  }
  return uri + "?immutable=1";
}

struct StatementDeleter {
  void operator()(sqlite3_stmt* s) const noexcept { sqlite3_finalize(s); }
};
using Statement = std::unique_ptr<sqlite3_stmt, StatementDeleter>;

class Sqlite3BagReader final : public BagReader {
 public:
  explicit Sqlite3BagReader(const BagReaderOptions& options) : options_(options) {}
  ~Sqlite3BagReader() override {
    statement_.reset();
    if (db_ != nullptr) sqlite3_close(db_);
  }

  std::optional<BagError> Open(const std::string& path);

  [[nodiscard]] BagFormat format() const noexcept override { return BagFormat::kRosbag2Sqlite3; }
  [[nodiscard]] const std::string& path() const noexcept override { return path_; }
  [[nodiscard]] const std::vector<BagTopic>& topics() const noexcept override { return topics_; }
  [[nodiscard]] Expected<bool, BagError> Next(BagRecord& out) override;

 private:
  BagError Error(BagErrorCode code, std::string text) const {
    return BagError{code, path_, 0, std::move(text)};
  }
  // The error of the last SQLite call: corruption and "not a database" are kMalformed.
  BagError SqliteError(const std::string& context) const {
    const int rc = sqlite3_extended_errcode(db_) & 0xff;
    const bool corrupt = rc == SQLITE_CORRUPT || rc == SQLITE_NOTADB || rc == SQLITE_FORMAT;
    return Error(corrupt ? BagErrorCode::kMalformed : BagErrorCode::kIo,
                 context + ": " + sqlite3_errmsg(db_));
  }
  Expected<Statement, BagError> Prepare(const std::string& sql) const {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &s, nullptr) != SQLITE_OK) {
      return Unexpected{SqliteError("cannot run '" + sql + "'")};
    }
    return Statement(s);
  }
  std::optional<BagError> CheckColumns(const char* table, std::initializer_list<const char*> need);
  std::optional<BagError> ReadTopics();

  BagReaderOptions options_;
  std::string path_;
  sqlite3* db_ = nullptr;
  Statement statement_;
  std::vector<BagTopic> topics_;
  std::unordered_map<std::int64_t, std::uint32_t> topic_of_id_;  // topics.id -> topics_ index
  std::optional<BagError> failed_;
};

std::optional<BagError> Sqlite3BagReader::CheckColumns(const char* table,
                                                       std::initializer_list<const char*> need) {
  auto info = Prepare(std::string("PRAGMA table_info(") + table + ")");
  if (!info) return info.error();
  std::set<std::string> have;
  int rc = SQLITE_ROW;
  while ((rc = sqlite3_step(info->get())) == SQLITE_ROW) {
    const auto* name = sqlite3_column_text(info->get(), 1);
    if (name != nullptr) have.insert(reinterpret_cast<const char*>(name));
  }
  if (rc != SQLITE_DONE) return SqliteError(std::string("cannot list the columns of ") + table);
  if (have.empty()) {
    return Error(BagErrorCode::kMalformed,
                 std::string("not a rosbag2 database: no table '") + table + "'");
  }
  for (const char* column : need) {
    if (!have.contains(column)) {
      return Error(BagErrorCode::kMalformed, std::string("not a rosbag2 database: table '") +
                                                 table + "' has no column '" + column + "'");
    }
  }
  return std::nullopt;
}

std::optional<BagError> Sqlite3BagReader::ReadTopics() {
  auto rows = Prepare("SELECT id, name, type, serialization_format FROM topics ORDER BY id");
  if (!rows) return rows.error();
  sqlite3_stmt* s = rows->get();
  int rc = SQLITE_ROW;
  while ((rc = sqlite3_step(s)) == SQLITE_ROW) {
    const std::int64_t id = sqlite3_column_int64(s, 0);
    const bool typed =
        sqlite3_column_type(s, 0) == SQLITE_INTEGER && sqlite3_column_type(s, 1) == SQLITE_TEXT &&
        sqlite3_column_type(s, 2) == SQLITE_TEXT && sqlite3_column_type(s, 3) == SQLITE_TEXT;
    if (!typed) {
      return Error(BagErrorCode::kMalformed,
                   "topics row " + std::to_string(id) +
                       ": id is not an integer or name, type, serialization_format not text");
    }
    BagTopic topic;
    topic.name = reinterpret_cast<const char*>(sqlite3_column_text(s, 1));
    topic.type_name = reinterpret_cast<const char*>(sqlite3_column_text(s, 2));
    topic.encoding = MessageEncodingOf(reinterpret_cast<const char*>(sqlite3_column_text(s, 3)));
    topic.kind = MessageKindOf(topic.type_name);
    // Counting would read the whole messages table before the first record: unknown (-1).
    if (!topic_of_id_.emplace(id, static_cast<std::uint32_t>(topics_.size())).second) {
      return Error(BagErrorCode::kMalformed, "topics id " + std::to_string(id) + " twice");
    }
    topics_.push_back(std::move(topic));
  }
  if (rc != SQLITE_DONE) return SqliteError("cannot read the topics table");
  return std::nullopt;
}

std::optional<BagError> Sqlite3BagReader::Open(const std::string& path) {
  path_ = path;
  {  // A clear "not a database" before SQLite's own, later, less specific one.
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error(BagErrorCode::kIo, "cannot open the file");
    char head[16] = {};
    in.read(head, sizeof head);
    if (std::string_view(head, static_cast<std::size_t>(in.gcount())) != kSqliteMagic) {
      return Error(BagErrorCode::kUnknownFormat,
                   "not a sqlite3 database (no 'SQLite format 3' magic)");
    }
  }
  const int flags = SQLITE_OPEN_READONLY | SQLITE_OPEN_URI | SQLITE_OPEN_NOMUTEX;
  if (sqlite3_open_v2(FileUri(path).c_str(), &db_, flags, nullptr) != SQLITE_OK) {
    return db_ != nullptr ? SqliteError("cannot open") : Error(BagErrorCode::kIo, "cannot open");
  }
  if (auto e = CheckColumns("topics", {"id", "name", "type", "serialization_format"})) return e;
  if (auto e = CheckColumns("messages", {"id", "topic_id", "timestamp", "data"})) return e;
  if (auto e = ReadTopics()) return e;
  auto statement =
      Prepare("SELECT topic_id, timestamp, data, id FROM messages ORDER BY timestamp, id");
  if (!statement) return statement.error();
  statement_ = std::move(*statement);
  return std::nullopt;
}

Expected<bool, BagError> Sqlite3BagReader::Next(BagRecord& out) {
  if (failed_) return Unexpected{*failed_};
  auto fail = [&](BagError error) -> Expected<bool, BagError> {
    failed_ = std::move(error);
    return Unexpected{*failed_};
  };
  sqlite3_stmt* s = statement_.get();
  const int rc = sqlite3_step(s);
  if (rc == SQLITE_DONE) return false;
  if (rc != SQLITE_ROW) return fail(SqliteError("cannot read the messages table"));
  auto row = [s] { return "messages row id " + std::to_string(sqlite3_column_int64(s, 3)); };
  if (sqlite3_column_type(s, 0) != SQLITE_INTEGER || sqlite3_column_type(s, 1) != SQLITE_INTEGER) {
    return fail(Error(BagErrorCode::kMalformed, row() + ": topic_id or timestamp not an integer"));
  }
  const auto topic = topic_of_id_.find(sqlite3_column_int64(s, 0));
  if (topic == topic_of_id_.end()) {
    return fail(Error(BagErrorCode::kMalformed, row() + ": topic_id " +
                                                    std::to_string(sqlite3_column_int64(s, 0)) +
                                                    ", which the topics table does not list"));
  }
  const int type = sqlite3_column_type(s, 2);
  if (type != SQLITE_BLOB && type != SQLITE_NULL) {
    return fail(Error(BagErrorCode::kMalformed, row() + ": data is not a blob"));
  }
  const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(s, 2));
  const auto size = static_cast<std::size_t>(sqlite3_column_bytes(s, 2));
  if (size > options_.max_chunk_bytes) {
    return fail(Error(BagErrorCode::kOverLimit, row() + ": data of " + std::to_string(size) +
                                                    " bytes, over the limit of " +
                                                    std::to_string(options_.max_chunk_bytes)));
  }
  const BagTopic& t = topics_[topic->second];
  out.topic = t.name;
  out.type_name = t.type_name;
  out.encoding = t.encoding;
  out.kind = t.kind;
  out.log_time_ns = sqlite3_column_int64(s, 1);
  out.data = size == 0 ? std::span<const std::uint8_t>() : std::span(data, size);
  return true;
}

Expected<BagReaderPtr, BagError> OpenFile(const std::string& path,
                                          const BagReaderOptions& options) {
  auto reader = std::make_unique<Sqlite3BagReader>(options);
  if (auto error = reader->Open(path)) return Unexpected{std::move(*error)};
  return BagReaderPtr(std::move(reader));
}

}  // namespace

Expected<BagReaderPtr, BagError> OpenRosbag2Sqlite3Bag(const std::string& path,
                                                       const BagReaderOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_directory(path, ec)) return OpenFile(path, options);
  auto meta = ReadRosbag2Metadata(path);
  if (!meta) return Unexpected{meta.error()};
  const std::string metadata_path = (std::filesystem::path(path) / "metadata.yaml").string();
  if (meta->storage_identifier != "sqlite3") {
    return Unexpected{BagError{
        BagErrorCode::kUnsupported, metadata_path, 0,
        "storage_identifier '" + meta->storage_identifier + "' in a folder opened as sqlite3"}};
  }
  if (!meta->compression_format.empty() ||
      !(meta->compression_mode.empty() || meta->compression_mode == "none")) {
    return Unexpected{BagError{BagErrorCode::kUnsupported, metadata_path, 0,
                               "rosbag2 compression '" + meta->compression_format + "' (mode '" +
                                   meta->compression_mode +
                                   "'): decompress the bag first (ros2 bag convert)"}};
  }
  std::vector<BagReaderPtr> parts;
  for (const std::string& file : meta->relative_file_paths) {
    auto part = OpenFile((std::filesystem::path(path) / file).string(), options);
    if (!part) return Unexpected{part.error()};
    parts.push_back(std::move(*part));
  }
  return MergeBagReaders(path, BagFormat::kRosbag2Sqlite3, std::move(parts));
}

}  // namespace semgraph::ros
