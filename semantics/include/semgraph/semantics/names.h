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
// Thread safety: const methods may run concurrently; Intern needs exclusive access.
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
  NameTable(NameTable&&) = default;
  NameTable& operator=(NameTable&&) = default;

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
    const char* text;
    std::uint32_t size;
    std::uint32_t hash;
  };
  static constexpr std::size_t kBlockBytes = 1 << 16;  // > kMaxNameBytes: a name never spans two
  static std::uint32_t Hash(std::string_view name) noexcept;
  std::size_t Probe(std::string_view name, std::uint32_t hash) const noexcept;  // slot index
  void Grow();
  void EraseSlot(std::size_t slot) noexcept;

  std::vector<std::unique_ptr<char[]>> blocks_;
  std::size_t block_fill_ = kBlockBytes;  // bytes used in blocks_.back()
  std::vector<Record> records_;           // by id
  std::vector<std::uint32_t> slots_;      // id + 1, or 0 for empty; size a power of two
};

}  // namespace semgraph::semantics
