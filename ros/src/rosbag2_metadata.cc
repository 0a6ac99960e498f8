// metadata.yaml of a rosbag2 bag folder: the storage identifier, the files and the compression.
#include "rosbag2_metadata.h"

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>

namespace semgraph::ros {
namespace {

constexpr std::uintmax_t kMaxMetadataBytes = 16u << 20;

struct Line {
  std::size_t offset = 0;  // of the line in the file
  std::size_t indent = 0;
  std::string_view text;  // without the indentation and the line end
};

std::vector<Line> SplitLines(std::string_view file) {
  std::vector<Line> lines;
  for (std::size_t pos = 0; pos < file.size();) {
    std::size_t end = file.find('\n', pos);
    if (end == std::string_view::npos) end = file.size();
    std::string_view text = file.substr(pos, end - pos);
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    const std::size_t indent = std::min(text.find_first_not_of(' '), text.size());
    text.remove_prefix(indent);
    if (!text.empty() && text.front() != '#') lines.push_back({pos, indent, text});
    pos = end + 1;
  }
  return lines;
}

// A YAML scalar: plain (up to a " #" comment), "double quoted" or 'single quoted'. nullopt when a
// quote is not closed.
std::optional<std::string> Scalar(std::string_view v) {
  while (!v.empty() && v.back() == ' ') v.remove_suffix(1);
  while (!v.empty() && v.front() == ' ') v.remove_prefix(1);
  if (v.empty()) return std::string();
  if (v.front() == '"' || v.front() == '\'') {
    const char quote = v.front();
    std::string out;
    for (std::size_t i = 1; i < v.size(); ++i) {
      if (quote == '"' && v[i] == '\\' && i + 1 < v.size()) {
        const char c = v[++i];
        out += c == 'n' ? '\n' : c == 't' ? '\t' : c;
      } else if (quote == '\'' && v[i] == '\'' && i + 1 < v.size() && v[i + 1] == '\'') {
        out += '\'';
        ++i;
      } else if (v[i] == quote) {
        return out;
      } else {
        out += v[i];
      }
    }
    return std::nullopt;
  }
  const std::size_t comment = v.find(" #");
  if (comment != std::string_view::npos) v = v.substr(0, comment);
  while (!v.empty() && v.back() == ' ') v.remove_suffix(1);
  return std::string(v);
}

// "key: value" -> (key, value); nullopt when the line is no mapping entry.
std::optional<std::pair<std::string_view, std::string_view>> Entry(std::string_view text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string_view::npos || colon == 0) return std::nullopt;
  if (colon + 1 < text.size() && text[colon + 1] != ' ') return std::nullopt;
  return std::make_pair(text.substr(0, colon), text.substr(std::min(colon + 1, text.size())));
}

}  // namespace

Expected<Rosbag2Metadata, BagError> ReadRosbag2Metadata(const std::string& folder) {
  const std::string path = (std::filesystem::path(folder) / "metadata.yaml").string();
  auto fail = [&](BagErrorCode code, std::size_t offset, std::string text) {
    return Unexpected{BagError{code, path, offset, std::move(text)}};
  };
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) return fail(BagErrorCode::kIo, 0, "cannot read: " + ec.message());
  if (size > kMaxMetadataBytes) {
    return fail(BagErrorCode::kOverLimit, 0, "metadata.yaml over 16 MiB");
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (!in) return fail(BagErrorCode::kIo, 0, "cannot read the file");
  const std::string file = buffer.str();
  const std::vector<Line> lines = SplitLines(file);

  std::size_t i = 0;
  while (i < lines.size() &&
         !(lines[i].indent == 0 && lines[i].text.starts_with("rosbag2_bagfile_information:"))) {
    ++i;
  }
  if (i == lines.size()) {
    return fail(BagErrorCode::kMalformed, 0, "no 'rosbag2_bagfile_information:' mapping");
  }
  const std::size_t root_end = ++i;
  const std::size_t child_indent = i < lines.size() ? lines[i].indent : 0;
  if (child_indent == 0) {
    return fail(BagErrorCode::kMalformed, lines[root_end - 1].offset,
                "'rosbag2_bagfile_information' has no entries");
  }
  Rosbag2Metadata meta;
  bool has_files = false;
  for (; i < lines.size() && lines[i].indent >= child_indent; ++i) {
    if (lines[i].indent != child_indent) continue;  // inside a nested entry
    const auto entry = Entry(lines[i].text);
    if (!entry) continue;
    const auto [key, rest] = *entry;
    auto value = Scalar(rest);
    if (!value) return fail(BagErrorCode::kMalformed, lines[i].offset, "unclosed quote");
    if (key == "storage_identifier") meta.storage_identifier = *value;
    if (key == "compression_format") meta.compression_format = *value;
    if (key == "compression_mode") meta.compression_mode = *value;
    if (key != "relative_file_paths") continue;
    has_files = true;
    std::string_view flow = rest;
    while (!flow.empty() && flow.front() == ' ') flow.remove_prefix(1);
    if (flow.starts_with("[")) {  // flow sequence on one line
      const std::size_t close = flow.find(']');
      if (close == std::string_view::npos) {
        return fail(BagErrorCode::kMalformed, lines[i].offset,
                    "unclosed '[' in relative_file_paths");
      }
      std::string_view items = flow.substr(1, close - 1);
      while (!items.empty()) {
        const std::size_t comma = std::min(items.find(','), items.size());
        auto item = Scalar(items.substr(0, comma));
        if (!item) return fail(BagErrorCode::kMalformed, lines[i].offset, "unclosed quote");
        if (!item->empty()) meta.relative_file_paths.push_back(*item);
        items.remove_prefix(std::min(comma + 1, items.size()));
      }
      continue;
    }
    // Block sequence: "- item" lines at this indentation or deeper.
    for (; i + 1 < lines.size() && lines[i + 1].indent >= child_indent &&
           lines[i + 1].text.starts_with("-");
         ++i) {
      auto item = Scalar(lines[i + 1].text.substr(1));
      if (!item) return fail(BagErrorCode::kMalformed, lines[i + 1].offset, "unclosed quote");
      meta.relative_file_paths.push_back(*item);
    }
  }
  if (meta.storage_identifier.empty()) {
    return fail(BagErrorCode::kMalformed, lines[root_end - 1].offset, "no storage_identifier");
  }
  if (!has_files || meta.relative_file_paths.empty()) {
    return fail(BagErrorCode::kMalformed, lines[root_end - 1].offset,
                "no relative_file_paths (the bag lists no storage file)");
  }
  for (const std::string& file_path : meta.relative_file_paths) {
    if (file_path.empty() || file_path.front() == '/') {
      return fail(BagErrorCode::kMalformed, lines[root_end - 1].offset,
                  "relative_file_paths entry '" + file_path + "' is not a relative path");
    }
  }
  return meta;
}

}  // namespace semgraph::ros
