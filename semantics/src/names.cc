#include "semgraph/semantics/names.h"

#include <cstring>
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

std::uint32_t NameTable::Hash(std::string_view name) noexcept {
  // FNV-1a, then a multiplicative finish so that the low bits used for probing mix well.
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const char c : name) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ull;
  }
  h ^= h >> 29;
  h *= 0xbf58476d1ce4e5b9ull;
  return static_cast<std::uint32_t>(h >> 32);
}

std::size_t NameTable::Probe(std::string_view name, std::uint32_t hash) const noexcept {
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t i = hash & mask;; i = (i + 1) & mask) {
    const std::uint32_t slot = slots_[i];
    if (slot == 0) return i;
    const Record& r = records_[slot - 1];
    if (r.hash == hash && std::string_view(r.text, r.size) == name) return i;
  }
}

void NameTable::Grow() {
  std::vector<std::uint32_t> old = std::move(slots_);
  slots_.assign(old.empty() ? 16 : 2 * old.size(), 0);
  const std::size_t mask = slots_.size() - 1;
  for (const std::uint32_t slot : old) {
    if (slot == 0) continue;
    std::size_t i = records_[slot - 1].hash & mask;
    while (slots_[i] != 0) i = (i + 1) & mask;
    slots_[i] = slot;
  }
}

Expected<NameId, NameError> NameTable::Intern(std::string_view name) {
  const Lookup found = FindWithHash(name);
  if (found.id.is_valid()) return found.id;
  if (auto valid = ValidateName(name); !valid) return Unexpected{valid.error()};
  return InternNew(name, found.hash);
}

void NameTable::Reserve(std::size_t n) {
  records_.reserve(n);
  while (2 * n > slots_.size()) Grow();
}

NameTable::Lookup NameTable::FindWithHash(std::string_view name) const noexcept {
  const std::uint32_t hash = Hash(name);
  if (slots_.empty()) return Lookup{NameId(), hash};
  const std::uint32_t slot = slots_[Probe(name, hash)];
  return Lookup{slot == 0 ? NameId() : NameId(slot - 1), hash};
}

NameId NameTable::InternNew(std::string_view name, std::uint32_t hash) {
  if (2 * (records_.size() + 1) > slots_.size()) Grow();
  if (block_fill_ + name.size() > kBlockBytes) {
    blocks_.push_back(std::make_unique<char[]>(kBlockBytes));
    block_fill_ = 0;
  }
  char* text = blocks_.back().get() + block_fill_;
  std::memcpy(text, name.data(), name.size());
  block_fill_ += name.size();
  const NameId id(static_cast<std::uint32_t>(records_.size()));
  records_.push_back(Record{text, static_cast<std::uint32_t>(name.size()), hash});
  slots_[Probe(name, hash)] = id.value() + 1;
  return id;
}

// Backward-shift deletion keeps every remaining name reachable from its home slot.
void NameTable::EraseSlot(std::size_t hole) noexcept {
  const std::size_t mask = slots_.size() - 1;
  slots_[hole] = 0;
  for (std::size_t j = (hole + 1) & mask; slots_[j] != 0; j = (j + 1) & mask) {
    const std::size_t home = records_[slots_[j] - 1].hash & mask;
    if (((j - home) & mask) >= ((j - hole) & mask)) {
      slots_[hole] = slots_[j];
      slots_[j] = 0;
      hole = j;
    }
  }
}

void NameTable::TruncateTo(std::size_t n) {
  while (records_.size() > n) {
    const Record r = records_.back();
    EraseSlot(Probe(std::string_view(r.text, r.size), r.hash));
    records_.pop_back();
    // Names were appended in order: give the arena bytes back (an emptied block is kept).
    if (!blocks_.empty() && r.text >= blocks_.back().get() &&
        r.text < blocks_.back().get() + kBlockBytes) {
      block_fill_ = static_cast<std::size_t>(r.text - blocks_.back().get());
    }
  }
}

NameId NameTable::Find(std::string_view name) const noexcept {
  if (slots_.empty()) return NameId();
  const std::uint32_t slot = slots_[Probe(name, Hash(name))];
  return slot == 0 ? NameId() : NameId(slot - 1);
}

std::string_view NameTable::name(NameId id) const noexcept {
  if (!id.is_valid() || id.value() >= records_.size()) return "<invalid>";
  const Record& r = records_[id.value()];
  return std::string_view(r.text, r.size);
}

std::size_t NameTable::ApproximateBytes() const noexcept {
  return blocks_.size() * kBlockBytes + records_.capacity() * sizeof(Record) +
         slots_.capacity() * sizeof(std::uint32_t) + blocks_.capacity() * sizeof(void*);
}

}  // namespace semgraph::semantics
