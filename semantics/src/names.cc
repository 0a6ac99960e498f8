#include "semgraph/semantics/names.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <string>
#include <utility>

#include "semgraph/base/utf8.h"

namespace semgraph::semantics {

namespace {
// The printable rule (docs/rules.md §1): which code points a name may not hold, and why.
enum class Unprintable : std::uint8_t {
  kNone,
  kControl,
  kInvisible,
  kSeparator,
  kSpace,
  kNoncharacter
};

struct Range {
  std::uint32_t first, last;
};
// Invisible or layout-changing characters: every format character (general category Cf) except
// the prepended concatenation marks, which print as visible signs (U+0600-0605, U+06DD, U+070F,
// U+0890-0891, U+08E2, U+110BD, U+110CD), and every default-ignorable code point (Unicode's list
// of characters a renderer shows as nothing: soft hyphen, zero-width characters, bidi controls,
// word joiner and invisible operators, byte-order mark, variation selectors, Hangul fillers,
// tag characters; assigned or reserved), as of Unicode 15. Sorted, disjoint.
constexpr Range kInvisible[] = {
    {0x00AD, 0x00AD},   {0x034F, 0x034F},   {0x061C, 0x061C},   {0x115F, 0x1160},
    {0x17B4, 0x17B5},   {0x180B, 0x180F},   {0x200B, 0x200F},   {0x202A, 0x202E},
    {0x2060, 0x206F},   {0x3164, 0x3164},   {0xFE00, 0xFE0F},   {0xFEFF, 0xFEFF},
    {0xFFA0, 0xFFA0},   {0xFFF0, 0xFFFB},   {0x13430, 0x1343F}, {0x1BCA0, 0x1BCA3},
    {0x1D173, 0x1D17A}, {0xE0000, 0xE0FFF},
};
// Space separators (Zs) other than U+0020: they print like an ASCII space but are other bytes.
constexpr Range kSpaces[] = {{0x00A0, 0x00A0}, {0x1680, 0x1680}, {0x2000, 0x200A},
                             {0x202F, 0x202F}, {0x205F, 0x205F}, {0x3000, 0x3000}};

bool InRanges(std::uint32_t cp, const Range* ranges, std::size_t n) noexcept {
  for (std::size_t k = 0; k < n && ranges[k].first <= cp; ++k) {
    if (cp <= ranges[k].last) return true;
  }
  return false;
}

Unprintable Classify(std::uint32_t cp) noexcept {
  if (cp < 0x20 || (cp >= 0x7F && cp <= 0x9F)) return Unprintable::kControl;
  if (cp < 0xA0) return Unprintable::kNone;  // the rest of ASCII is printable
  if (cp == 0x2028 || cp == 0x2029) return Unprintable::kSeparator;
  if ((cp >= 0xFDD0 && cp <= 0xFDEF) || (cp & 0xFFFE) == 0xFFFE) return Unprintable::kNoncharacter;
  if (InRanges(cp, kSpaces, std::size(kSpaces))) return Unprintable::kSpace;
  if (InRanges(cp, kInvisible, std::size(kInvisible))) return Unprintable::kInvisible;
  return Unprintable::kNone;
}

// "U+200B" (at least four hex digits).
std::string CodePointText(std::uint32_t cp) {
  char buf[16];
  std::snprintf(buf, sizeof(buf), "U+%04X", static_cast<unsigned>(cp));
  return buf;
}
}  // namespace

Expected<Ok, NameError> ValidateName(std::string_view name) noexcept {
  if (name.empty()) return Unexpected{NameError{ErrorCode::kInvalidName, NameProblem::kEmpty, 0}};
  if (name.size() > kMaxNameBytes) {
    return Unexpected{NameError{ErrorCode::kInvalidName, NameProblem::kTooLong, kMaxNameBytes}};
  }
  for (std::size_t i = 0; i < name.size();) {
    const auto b = static_cast<unsigned char>(name[i]);
    if (b >= 0x20 && b < 0x7F) {  // printable ASCII: the common case
      ++i;
      continue;
    }
    const auto [n, cp] = base::DecodeUtf8(name, i);
    if (n == 0) return Unexpected{NameError{ErrorCode::kInvalidName, NameProblem::kNotUtf8, i}};
    if (Classify(cp) != Unprintable::kNone) {
      return Unexpected{NameError{ErrorCode::kInvalidName, NameProblem::kNotPrintable, i, cp}};
    }
    i += n;
  }
  return Ok{};
}

std::string Describe(const NameError& error, std::string_view name) {
  const std::string at = "byte " + std::to_string(error.byte_offset) + " of the name is ";
  switch (error.problem) {
    case NameProblem::kEmpty:
      return "name is empty";
    case NameProblem::kTooLong:
      return "name is " + std::to_string(name.size()) + " bytes long (at most " +
             std::to_string(kMaxNameBytes) + ")";
    case NameProblem::kNotPrintable:
      switch (Classify(error.code_point)) {
        case Unprintable::kInvisible:
          return at + CodePointText(error.code_point) + ", an invisible or formatting character";
        case Unprintable::kSeparator:
          return at + CodePointText(error.code_point) + ", a line or paragraph separator";
        case Unprintable::kSpace:
          return at + CodePointText(error.code_point) + ", a space other than U+0020";
        case Unprintable::kNoncharacter:
          return at + CodePointText(error.code_point) + ", a noncharacter";
        case Unprintable::kControl:
        case Unprintable::kNone:
          break;
      }
      return at + "a control character";
    case NameProblem::kNotUtf8:
      return at + "not valid UTF-8";
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

namespace {
// Text bytes are atomic too: TruncateTo gives arena bytes back, and a later name may be written
// over a dropped one while a reader still compares it (the reader's validation then fails).
bool SameText(const char* text, std::string_view name) noexcept {
  for (std::size_t i = 0; i < name.size(); ++i) {
    if (std::atomic_ref<char>(const_cast<char&>(text[i])).load(std::memory_order_acquire) !=
        name[i])
      return false;
  }
  return true;
}
void WriteText(char* text, std::string_view name) noexcept {
  for (std::size_t i = 0; i < name.size(); ++i)
    std::atomic_ref<char>(text[i]).store(name[i], std::memory_order_release);
}
}  // namespace

NameTable& NameTable::operator=(NameTable&& other) noexcept {
  blocks_ = std::move(other.blocks_);
  block_fill_ = std::exchange(other.block_fill_, kBlockBytes);
  records_ = std::move(other.records_);
  tables_ = std::move(other.tables_);
  other.tables_.clear();
  index_slots_ = std::exchange(other.index_slots_, 0);
  slots_ = other.slots_.load();
  mask_ = other.mask_.load();
  other.slots_ = nullptr;
  other.mask_ = 0;
  return *this;
}

std::size_t NameTable::Probe(const Slot* slots, std::size_t mask,
                             const base::RetiringArray<Record>& records, std::string_view name,
                             std::uint32_t hash) noexcept {
  const std::size_t n = records.size();
  std::size_t i = hash & mask;
  for (std::size_t probes = 0; probes <= mask; ++probes, i = (i + 1) & mask) {
    const std::uint32_t slot = slots[i];
    if (slot == 0 || slot > n) return i;  // > n: a reader racing a TruncateTo
    const Record& r = records[slot - 1];
    if (r.hash == hash && r.size == name.size() && SameText(r.text, name)) return i;
  }
  return i;
}

void NameTable::Grow(std::size_t size) {
  // The new index is filled before it is published: an allocation failure leaves the table as
  // it was, and a reader sees the old index or the new one, each whole. The old one stays
  // allocated (tables_), since a reader may still be probing it.
  if (tables_.size() == tables_.capacity()) tables_.reserve(2 * tables_.size() + 4);
  auto grown = std::make_unique<Slot[]>(size);
  const std::size_t mask = size - 1;
  const Slot* old = slots_;
  for (std::size_t k = 0; k < capacity(); ++k) {
    const std::uint32_t slot = old[k];
    if (slot == 0) continue;
    std::size_t i = records_[slot - 1].hash & mask;
    while (grown[i] != 0) i = (i + 1) & mask;
    grown[i] = slot;
  }
  slots_ = grown.get();
  mask_ = mask;
  tables_.push_back(std::move(grown));  // within capacity: cannot throw
  index_slots_ += size;
}

Expected<NameId, NameError> NameTable::Intern(std::string_view name) {
  const Lookup found = FindWithHash(name);
  if (found.id.is_valid()) return found.id;
  if (auto valid = ValidateName(name); !valid) return Unexpected{valid.error()};
  return InternNew(name, found.hash);
}

void NameTable::Reserve(std::size_t n) {
  records_.reserve(n);
  if (2 * n > capacity()) Grow(std::bit_ceil(std::max<std::size_t>(16, 2 * n)));
}

NameTable::Lookup NameTable::FindWithHash(std::string_view name) const noexcept {
  const std::uint32_t hash = Hash(name);
  const std::size_t mask = mask_;
  const Slot* slots = slots_;
  if (!slots) return Lookup{NameId(), hash};
  const std::uint32_t slot = slots[Probe(slots, mask, records_, name, hash)];
  return Lookup{slot == 0 ? NameId() : NameId(slot - 1), hash};
}

NameId NameTable::InternNew(std::string_view name, std::uint32_t hash) {
  // Every allocation first (index, record array, a new arena block), each of which leaves the
  // table unchanged when it fails; then the name goes in without allocating.
  if (2 * (records_.size() + 1) > capacity()) Grow(tables_.empty() ? 16 : 2 * capacity());
  if (records_.size() == records_.capacity())
    records_.reserve(std::max<std::size_t>(16, 2 * records_.size()));
  if (block_fill_ + name.size() > kBlockBytes) {
    if (blocks_.size() == blocks_.capacity())
      blocks_.reserve(std::max<std::size_t>(4, 2 * blocks_.size()));
    auto block = std::make_unique<char[]>(kBlockBytes);
    blocks_.push_back(std::move(block));  // within capacity: cannot throw
    block_fill_ = 0;
  }
  char* text = blocks_.back().get() + block_fill_;
  WriteText(text, name);
  block_fill_ += name.size();
  // The text, then the record, then the index slot (release): a reader that finds the slot
  // reads the whole name.
  const NameId id(static_cast<std::uint32_t>(records_.size()));
  records_.push_back(Record{text, static_cast<std::uint32_t>(name.size()), hash});
  slots_.load()[Probe(name, hash)] = id.value() + 1;
  return id;
}

// Backward-shift deletion keeps every remaining name reachable from its home slot.
void NameTable::EraseSlot(std::size_t hole) noexcept {
  const std::size_t mask = mask_;
  Slot* slots = slots_;
  slots[hole] = 0;
  for (std::size_t j = (hole + 1) & mask; slots[j] != 0; j = (j + 1) & mask) {
    const std::size_t home = records_[slots[j] - 1].hash & mask;
    if (((j - home) & mask) >= ((j - hole) & mask)) {
      slots[hole] = slots[j].load();
      slots[j] = 0;
      hole = j;
    }
  }
}

void NameTable::TruncateTo(std::size_t n) {
  while (records_.size() > n) {
    const Record& r = records_.back();
    const char* text = r.text;
    EraseSlot(Probe(std::string_view(text, r.size), r.hash));
    records_.PopBack();
    // Names were appended in order: give the arena bytes back (an emptied block is kept).
    if (!blocks_.empty() && text >= blocks_.back().get() &&
        text < blocks_.back().get() + kBlockBytes) {
      block_fill_ = static_cast<std::size_t>(text - blocks_.back().get());
    }
  }
}

NameId NameTable::Find(std::string_view name) const noexcept { return FindWithHash(name).id; }

std::string_view NameTable::name(NameId id) const noexcept {
  if (!id.is_valid() || id.value() >= records_.size()) return "<invalid>";
  const Record& r = records_[id.value()];
  return std::string_view(r.text, r.size);
}

std::size_t NameTable::ApproximateBytes() const noexcept {
  return blocks_.size() * kBlockBytes + records_.bytes() + index_slots_ * sizeof(Slot) +
         blocks_.capacity() * sizeof(void*);
}

}  // namespace semgraph::semantics
