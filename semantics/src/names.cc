#include "semgraph/semantics/names.h"

#include <string>

namespace semgraph::semantics {

namespace {
// Length of the UTF-8 sequence starting at s[i], or 0 if it is not a valid, shortest-form,
// non-surrogate sequence.
std::size_t Utf8SequenceLength(std::string_view s, std::size_t i) noexcept {
  const auto b0 = static_cast<unsigned char>(s[i]);
  std::size_t n;
  std::uint32_t cp;
  if (b0 < 0x80) return 1;
  if ((b0 & 0xE0) == 0xC0) {
    n = 2;
    cp = b0 & 0x1F;
  } else if ((b0 & 0xF0) == 0xE0) {
    n = 3;
    cp = b0 & 0x0F;
  } else if ((b0 & 0xF8) == 0xF0) {
    n = 4;
    cp = b0 & 0x07;
  } else {
    return 0;
  }
  if (i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    const auto b = static_cast<unsigned char>(s[i + k]);
    if ((b & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (b & 0x3F);
  }
  const std::uint32_t min_cp[] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < min_cp[n] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
  return n;
}

// True when s[i] starts a C1 control character (U+0080..U+009F, shortest form C2 80..C2 9F):
// valid UTF-8, but not printable.
bool IsC1Control(std::string_view s, std::size_t i) noexcept {
  return static_cast<unsigned char>(s[i]) == 0xC2 && i + 1 < s.size() &&
         (static_cast<unsigned char>(s[i + 1]) & 0xE0) == 0x80;
}
}  // namespace

Expected<Ok, NameError> ValidateName(std::string_view name) noexcept {
  if (name.empty()) return Unexpected{NameError{ErrorCode::kInvalidName, NameProblem::kEmpty, 0}};
  if (name.size() > kMaxNameBytes) {
    return Unexpected{NameError{ErrorCode::kInvalidName, NameProblem::kTooLong, kMaxNameBytes}};
  }
  for (std::size_t i = 0; i < name.size();) {
    const auto b = static_cast<unsigned char>(name[i]);
    if (b < 0x80) {
      if (b < 0x20 || b == 0x7F) {
        return Unexpected{NameError{ErrorCode::kInvalidName, NameProblem::kNotPrintable, i}};
      }
      ++i;
      continue;
    }
    if (IsC1Control(name, i)) {
      return Unexpected{NameError{ErrorCode::kInvalidName, NameProblem::kNotPrintable, i}};
    }
    const std::size_t n = Utf8SequenceLength(name, i);
    if (n == 0) return Unexpected{NameError{ErrorCode::kInvalidName, NameProblem::kNotUtf8, i}};
    i += n;
  }
  return Ok{};
}

std::string Describe(const NameError& error, std::string_view name) {
  switch (error.problem) {
    case NameProblem::kEmpty:
      return "name is empty";
    case NameProblem::kTooLong:
      return "name is " + std::to_string(name.size()) + " bytes long (at most " +
             std::to_string(kMaxNameBytes) + ")";
    case NameProblem::kNotPrintable:
      return "byte " + std::to_string(error.byte_offset) + " of the name is a control character";
    case NameProblem::kNotUtf8:
      return "byte " + std::to_string(error.byte_offset) + " of the name is not valid UTF-8";
  }
  return "invalid name";
}

Expected<NameId, NameError> NameTable::Intern(std::string_view name) {
  if (const auto it = ids_.find(name); it != ids_.end()) return it->second;
  if (auto valid = ValidateName(name); !valid) return Unexpected{valid.error()};
  const NameId id(static_cast<std::uint32_t>(names_.size()));
  const std::string& stored = names_.emplace_back(name);
  ids_.emplace(std::string_view(stored), id);
  return id;
}

void NameTable::TruncateTo(std::size_t n) {
  while (names_.size() > n) {
    ids_.erase(std::string_view(names_.back()));
    names_.pop_back();
  }
}

NameId NameTable::Find(std::string_view name) const noexcept {
  const auto it = ids_.find(name);
  return it == ids_.end() ? NameId() : it->second;
}

std::string_view NameTable::name(NameId id) const noexcept {
  if (!id.is_valid() || id.value() >= names_.size()) return "<invalid>";
  return names_[id.value()];
}

std::size_t NameTable::ApproximateBytes() const noexcept {
  std::size_t bytes = 0;
  for (const std::string& s : names_) bytes += sizeof(std::string) + (s.size() > 15 ? s.capacity() : 0);
  // unordered_map: one node per entry (key, value, next pointer, cached hash) plus buckets.
  bytes += ids_.size() * (sizeof(std::string_view) + sizeof(NameId) + 2 * sizeof(void*));
  bytes += ids_.bucket_count() * sizeof(void*);
  return bytes;
}

}  // namespace semgraph::semantics
