// File: semgraph/semantics/names.h
//
// NameTable: interns the names of points, orientation frames, frames and bodies into small
// dense ids (NameId), once, at build time. Every semantic check afterwards compares ids, never
// strings.
//
// Invariants:
//  - ids are dense: 0 .. size()-1, in order of first interning; an id never changes or dies.
//  - every interned name is valid: non-empty, at most kMaxNameBytes bytes, valid UTF-8 and
//    printable: no control characters, no invisible or formatting characters (format
//    characters and default-ignorable code points), no line or paragraph separators, no spaces
//    other than U+0020, no noncharacters (the definition and its reasons: docs/rules.md §1).
// Costs: Intern O(|name|) amortized (one hash, one copy into a 64 KiB arena on first sight; no
// allocation per name); Find O(|name|), allocation-free; name(id) O(1).
// Thread safety: one writer (Intern, InternNew, Reserve, TruncateTo) and any number of readers
// of Find, FindWithHash, name and size, which never crash or read freed memory while the
// writer changes the table: records live in a RetiringArray (old arrays kept), the index is
// published through an atomic pointer and mask and every index ever made is kept until the table
// dies (at most twice the current one's size), and every field and text byte a reader reads is
// atomic (base::Published, release stores / acquire loads). A reader's answer is meaningful when it
// validates that no change overlapped (SceneTopology's change counter, docs/realtime.md);
// without a concurrent writer it is exact. name(id)'s view is for the writer's thread (or text
// no change can touch: names are never rewritten except after a TruncateTo that dropped them).
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "semgraph/base/error_code.h"
#include "semgraph/base/expected.h"
#include "semgraph/base/index.h"
#include "semgraph/base/published.h"
#include "semgraph/base/retiring_array.h"
#include "semgraph/semantics/export.h"

namespace semgraph::semantics {

// The foundations this layer's API is written in.
using base::ErrorCode;
using base::Expected;
using base::Ok;
using base::Unexpected;

/// A dense id for an interned name. Default-constructed ids are invalid.
struct NameTag {};
using NameId = base::StrongIndex<NameTag>;

inline constexpr std::size_t kMaxNameBytes = 255;

/// Why a name is invalid (for the message); the code is always kInvalidName.
enum class NameProblem : std::uint8_t { kEmpty, kTooLong, kNotPrintable, kNotUtf8 };

struct NameError {
  ErrorCode code = ErrorCode::kInvalidName;
  NameProblem problem = NameProblem::kEmpty;
  std::size_t byte_offset = 0;   ///< offending byte for kNotPrintable / kNotUtf8
  std::uint32_t code_point = 0;  ///< the character that is not printable (kNotPrintable)
};

/// Checks the name rule without interning. O(|name|), allocation-free.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Expected<Ok, NameError> ValidateName(
    std::string_view name) noexcept;

/// Human-readable reason, e.g. "name is empty", "byte 3 of the name is a control character",
/// "byte 0 of the name is U+200B, an invisible or formatting character".
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string Describe(const NameError& error,
                                                             std::string_view name);

class SEMGRAPH_SEMANTICS_EXPORT NameTable {
 public:
  NameTable() = default;
  NameTable(const NameTable&) = delete;  // returned string_views point into the arena
  NameTable& operator=(const NameTable&) = delete;
  NameTable(NameTable&& other) noexcept { *this = std::move(other); }
  NameTable& operator=(NameTable&& other) noexcept;

  /// Returns the id of `name`, interning it on first sight. Fails with kInvalidName.
  [[nodiscard]] Expected<NameId, NameError> Intern(std::string_view name);

  /// The id of an already interned name, or an invalid id. Allocation-free.
  [[nodiscard]] NameId Find(std::string_view name) const noexcept;

  /// Find, also giving the name's hash, so that a build operation that looks a name up and
  /// then interns it hashes it once (InternNew).
  struct Lookup {
    NameId id;
    std::uint32_t hash = 0;
  };
  [[nodiscard]] Lookup FindWithHash(std::string_view name) const noexcept;
  /// Interns a name known to be valid and not interned, with its hash from FindWithHash.
  NameId InternNew(std::string_view name, std::uint32_t hash);

  /// The text of an interned id; "<invalid>" for an invalid id. O(1). The view stays valid for
  /// the table's lifetime (until TruncateTo drops the name): the text never moves.
  [[nodiscard]] std::string_view name(NameId id) const noexcept;

  [[nodiscard]] std::size_t size() const noexcept { return records_.size(); }
  /// Room for `n` names in total in the index (the text arena grows by blocks anyway).
  void Reserve(std::size_t n);

  /// Forgets every name interned after the first `n` (build-time rollback, so that a rejected
  /// operation leaves the table exactly as it was, arena space included). O(names dropped).
  void TruncateTo(std::size_t n);

  /// Heap bytes held by the names and the index (for memory reports).
  [[nodiscard]] std::size_t ApproximateBytes() const noexcept;

 private:
  // Names are stored back to back in fixed-size blocks that never move (so views stay valid),
  // indexed by an open-addressing table of ids (linear probing, load <= 1/2): no allocation per
  // name, one hash per lookup.
  struct Record {
    base::Published<const char*> text;
    base::Published<std::uint32_t> size;
    base::Published<std::uint32_t> hash;
  };
  using Slot = base::Published<std::uint32_t>;         // id + 1, or 0 for empty
  static constexpr std::size_t kBlockBytes = 1 << 16;  // > kMaxNameBytes: a name never spans two
  static std::uint32_t Hash(std::string_view name) noexcept;
  // The slot of `name` in `slots` (mask + 1 of them), or of the free slot ending its probe run;
  // at most mask + 1 probes (a reader racing the writer may see no free slot).
  static std::size_t Probe(const Slot* slots, std::size_t mask,
                           const base::RetiringArray<Record>& r, std::string_view name,
                           std::uint32_t hash) noexcept;
  std::size_t Probe(std::string_view name, std::uint32_t hash) const noexcept {
    return Probe(slots_.load(), mask_.load(), records_, name, hash);
  }
  void Grow(std::size_t size);  // a new index of `size` slots (a power of two)
  void EraseSlot(std::size_t slot) noexcept;
  [[nodiscard]] std::size_t capacity() const noexcept { return tables_.empty() ? 0 : mask_ + 1; }

  std::vector<std::unique_ptr<char[]>> blocks_;
  std::size_t block_fill_ = kBlockBytes;  // bytes used in blocks_.back()
  base::RetiringArray<Record> records_;   // by id
  // Every index made (the current one last; older ones kept for readers that may still probe
  // them), and the current one published: slots then mask (writer), mask then slots (reader),
  // so a reader never pairs a larger mask with a smaller array.
  std::vector<std::unique_ptr<Slot[]>> tables_;
  base::Published<Slot*> slots_ = nullptr;
  base::Published<std::size_t> mask_ = 0;
  std::size_t index_slots_ = 0;  // slots of every index in tables_ (memory report)
};

}  // namespace semgraph::semantics
