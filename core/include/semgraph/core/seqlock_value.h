// File: semgraph/core/seqlock_value.h
//
// SeqLockValue<T>: one edge value (a pose or a twist) that one writer thread may update while
// any number of reader threads read it, without locks and without torn reads: a sequence lock
// over atomic words. The writer stores them atomically; readers load them with acquire loads
// (portable path, and every ThreadSanitizer build, which checks it: no standalone fences, which
// GCC's TSan does not support) or, on x86-64, with plain SSE loads in inline assembly, which are
// atomic and ordered by the x86-64 memory model (see LoadWord for why). It also carries the
// edge's *epoch*: a counter bumped when the edge is removed, so that a compiled query built on the
// edge notices, instead of reading a stranger's value.
//
// Header word: high 32 bits = epoch, low 32 bits = sequence (odd while a write is in progress).
// Invariants: the sequence is even between writes; readers return a value that some completed
// Store wrote (never a mix of two writes).
// Costs: Store = 2 header stores + sizeof(T)/8 word stores; Load = 2 header loads + the word
// loads (plain moves on x86-64), retried only when a write overlapped the read.
// Thread safety: one writer at a time (per value); readers concurrent with it. Copying is only
// allowed with exclusive access (the graph's values never move: stable_array.h).
#pragma once

#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>

namespace semgraph::core {

/// Bytes: how many leading bytes of T carry data (a value type's tail padding need not be
/// copied: the quaternion pose is 56 bytes of data in a 64-byte type, so header + data fill
/// exactly one 64-byte cache line).
template <class T, std::size_t Bytes = sizeof(T)>
class alignas(8 + ((Bytes + 7) / 8) * 8 <= 64 ? 64 : 8) SeqLockValue {
 public:
  static_assert(Bytes <= sizeof(T));
  static constexpr std::size_t kWords = (Bytes + 7) / 8;
  // The payload is copied bit for bit through 8-byte words typed double: every value stored
  // here is made of doubles, and the reader loads them straight into SSE registers (see
  // LoadWord). Bits round-trip exactly (memcpy in, memcpy out).
  using Word = double;
  static_assert(std::atomic<Word>::is_always_lock_free);

  SeqLockValue() noexcept = default;
  explicit SeqLockValue(const T& value) noexcept { Store(value); }
  // Exclusive access only (vector growth during the build phase).
  SeqLockValue(const SeqLockValue& other) noexcept {
    header_.store(other.header_.load(std::memory_order_relaxed) & ~kSeqMask,
                  std::memory_order_relaxed);
    for (std::size_t i = 0; i < kWords; ++i) {
      words_[i].store(other.words_[i].load(std::memory_order_relaxed), std::memory_order_relaxed);
    }
  }
  SeqLockValue& operator=(const SeqLockValue&) = delete;

  /// Single writer. Never blocks readers for longer than the copy of kWords words.
  void Store(const T& value) noexcept {
    Word words[kWords] = {};
    std::memcpy(static_cast<void*>(words), static_cast<const void*>(&value), Bytes);
    const std::uint64_t h = header_.load(std::memory_order_relaxed);
    header_.store(NextSeq(h), std::memory_order_relaxed);  // odd: write in progress
    // Release stores of the words order the odd header before them: a reader that sees any
    // new word (acquire) also sees the odd header on its re-check. No fences (TSan-friendly);
    // on x86-64 release stores and acquire loads are plain moves.
    for (std::size_t i = 0; i < kWords; ++i) words_[i].store(words[i], std::memory_order_release);
    header_.store(NextSeq(NextSeq(h)), std::memory_order_release);  // even again
  }

  /// Reads a consistent value if the epoch is still `epoch`; false (out untouched) otherwise.
  [[nodiscard]] bool Load(T& out, std::uint32_t epoch) const noexcept {
    Word words[kWords];
    for (;;) {
      const std::uint64_t h1 = header_.load(std::memory_order_acquire);
      if (Epoch(h1) != epoch) return false;
      if (h1 & 1u) continue;  // a write is in progress; it is a handful of stores
      // Acquire loads keep the header re-check below after every word load; unrolled, so the
      // words go straight to registers.
      LoadWords(words, std::make_index_sequence<kWords>{});
      if (header_.load(std::memory_order_relaxed) == h1) break;
    }
    std::memcpy(static_cast<void*>(&out), static_cast<const void*>(words), Bytes);
    return true;
  }

  /// What LoadWords expects of the header of a value at `epoch` (precomputed once per edge of a
  /// compiled query, so that the hot loop tests epoch and write-in-progress in one instruction).
  static constexpr std::uint64_t ExpectedHeader(std::uint32_t epoch) noexcept {
    return static_cast<std::uint64_t>(epoch) << 32;
  }

  /// The raw words (bit copies of T) of a consistent value if the epoch is still the one of
  /// `expected_header` (= ExpectedHeader(epoch)), for callers that rebuild T in registers (the
  /// compiled-query hot loop); false otherwise.
  [[nodiscard]] bool LoadWords(Word (&words)[kWords],
                               std::uint64_t expected_header) const noexcept {
    std::uint64_t header;  // unused: optimised away once inlined
    return LoadWords(words, expected_header, header);
  }

  /// Two words per lane pair, for callers that compute on lane pairs (motion_pairs.h): the
  /// same consistent read as LoadWords, with pairs[i] = (word Lo_i, word Hi_i), each pair loaded
  /// straight into one vector register (no shuffle, no copy through memory on x86-64). A word
  /// may appear in several pairs.
  using WordPair = Word __attribute__((vector_size(16)));
  template <std::size_t... Lo, std::size_t... Hi>
  [[nodiscard]] bool LoadWordPairs(WordPair (&pairs)[sizeof...(Lo)], std::index_sequence<Lo...> lo,
                                   std::index_sequence<Hi...> hi,
                                   std::uint64_t expected_header) const noexcept {
    static_assert(sizeof...(Lo) == sizeof...(Hi) && ((Lo < kWords && Hi < kWords) && ...));
    std::uint64_t header;  // unused: optimised away once inlined
    return ReadConsistent(expected_header, header, [&](std::uint64_t& token) {
      LoadPairs(pairs, std::make_index_sequence<sizeof...(Lo)>{}, lo, hi, token);
    });
  }

  /// The current header (epoch << 32 | sequence): a reader that cached a value together with the
  /// header it was read under knows the value is unchanged while the header is. Acquire load.
  [[nodiscard]] std::uint64_t header() const noexcept {
    return header_.load(std::memory_order_acquire);
  }

  /// A consistent value and the header it was read under, if the epoch is still the one of
  /// `expected_header`; false otherwise.
  [[nodiscard]] bool LoadWithHeader(T& out, std::uint64_t expected_header,
                                    std::uint64_t& header) const noexcept {
    Word words[kWords];
    if (!LoadWords(words, expected_header, header)) return false;
    std::memcpy(static_cast<void*>(&out), static_cast<const void*>(words), Bytes);
    return true;
  }

  /// The raw words of a consistent value whatever the epoch (the one-shot query path, which
  /// holds no epoch: it reads the graph as it is).
  void LoadWords(Word (&words)[kWords]) const noexcept {
    ReadAnyEpoch([&] { LoadWords(words, std::make_index_sequence<kWords>{}); });
  }

  /// Selected words of a consistent value whatever the epoch: word I_k into head[k] and word
  /// J_k into dest[k * kStride], straight from the value to where the caller computes on them (a
  /// compiled query's SIMD lanes, covariance_lanes.h: no copy of the whole value; a constant
  /// stride makes every store one instruction).
  template <std::size_t kStride, std::size_t... I, std::size_t... J>
  void LoadSelectedWords(Word (&head)[sizeof...(I)], std::index_sequence<I...> head_words,
                         Word* dest, std::index_sequence<J...> dest_words) const noexcept {
    static_assert(((I < kWords) && ...) && ((J < kWords) && ...));
    ReadAnyEpoch([&] {
      LoadStrided<1>(head, std::make_index_sequence<sizeof...(I)>{}, head_words);
      LoadStrided<kStride>(dest, std::make_index_sequence<sizeof...(J)>{}, dest_words);
    });
  }

  /// Reads a consistent value whatever the epoch.
  [[nodiscard]] T Load() const noexcept {
    T out;
    while (!Load(out, epoch())) {
    }
    return out;
  }

  [[nodiscard]] std::uint32_t epoch() const noexcept {
    return Epoch(header_.load(std::memory_order_acquire));
  }
  /// Exclusive access: the edge was removed; compiled queries holding the old epoch fail.
  void BumpEpoch() noexcept {
    const std::uint64_t h = header_.load(std::memory_order_relaxed);
    header_.store(((h >> 32) + 1) << 32 | (h & kSeqMask), std::memory_order_release);
  }

 private:
  // The one epoch-checked read (LoadWords, LoadWithHeader, LoadWordPairs): `read(token)` loads
  // the words (the caller's way) between the header load and its re-check; true, with the header
  // they were read under, if the epoch is still the one of `expected_header`; false otherwise.
  // Order: the reads take the token (the header read) and pass it on, and the re-check takes it
  // back, so data dependencies keep them in order (LoadPair); LoadWords orders its words with
  // compiler barriers instead.
  template <class Read>
  [[nodiscard, gnu::always_inline]] bool ReadConsistent(std::uint64_t expected_header,
                                                        std::uint64_t& header,
                                                        Read read) const noexcept {
    for (;;) {
      const std::uint64_t h1 = header_.load(std::memory_order_acquire);
      if ((h1 ^ expected_header) & kCheckMask) {  // another epoch, or a write in progress
        if ((h1 ^ expected_header) >> 32) return false;
        continue;
      }
      std::uint64_t token = h1;
      read(token);
      if (HeaderAfter(token) == h1) {
        header = h1;
        return true;
      }
    }
  }
  [[nodiscard]] bool LoadWords(Word (&words)[kWords], std::uint64_t expected_header,
                               std::uint64_t& header) const noexcept {
    return ReadConsistent(expected_header, header, [&](std::uint64_t&) {
      LoadWords(words, std::make_index_sequence<kWords>{});
    });
  }

  // The one read whatever the epoch: read() between the header load and its re-check. The
  // first try is not in a loop: in one, GCC hoisted the words' addresses out of it and kept them
  // on the stack (a load of each address per word); retries are out of line.
  template <class Read>
  [[gnu::always_inline]] void ReadAnyEpoch(Read read) const noexcept {
    const std::uint64_t h1 = header_.load(std::memory_order_acquire);
    if ((h1 & 1u) == 0) {  // else a write is in progress; it is a handful of stores
      read();
      if (header_.load(std::memory_order_relaxed) == h1) return;
    }
    RetryAnyEpoch(read);
  }
  template <class Read>
  [[gnu::noinline, gnu::cold]] void RetryAnyEpoch(Read read) const noexcept {
    for (;;) {
      const std::uint64_t h1 = header_.load(std::memory_order_acquire);
      if (h1 & 1u) continue;
      read();
      if (header_.load(std::memory_order_relaxed) == h1) return;
    }
  }
  // Word to memory, so acquire loads (plain moves on x86-64) rather than LoadWord's SSE loads:
  // each word goes through a general register at a constant offset (the asm's memory operands
  // made GCC keep 60 addresses per record on the stack). Acquire keeps the re-check after them.
  template <std::size_t kStride, std::size_t... K, std::size_t... W>
  void LoadStrided(Word* out, std::index_sequence<K...>, std::index_sequence<W...>) const noexcept {
    ((out[K * kStride] = words_[W].load(std::memory_order_acquire)), ...);
  }
  template <std::size_t... I>
  void LoadWords(Word* words, std::index_sequence<I...>) const noexcept {
    CompilerBarrier();  // the word loads stay between the header load and its re-check
    (LoadWord(words[I], words_[I]), ...);
    CompilerBarrier();
  }
  template <std::size_t... I, std::size_t... Lo, std::size_t... Hi>
  void LoadPairs(WordPair* pairs, std::index_sequence<I...>, std::index_sequence<Lo...>,
                 std::index_sequence<Hi...>, std::uint64_t& token) const noexcept {
    (LoadPair(pairs[I], words_[Lo], words_[Hi], token), ...);
  }

#if defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define SEMGRAPH_SEQLOCK_TSAN 1
#endif
#endif
#if defined(__SANITIZE_THREAD__)
#define SEMGRAPH_SEQLOCK_TSAN 1
#endif
#if defined(__x86_64__) && !defined(SEMGRAPH_SEQLOCK_TSAN)
  // x86-64: one `movsd` per word, straight into an SSE register. An aligned 8-byte load is
  // atomic on x86-64, and loads are not reordered with loads (x86-TSO), so header, words and
  // header re-check are read in program order as long as the compiler keeps them in that order,
  // which the two compiler barriers around the word loads ensure. Why not
  // std::atomic<double>::load: GCC routes it through a general register, and in the
  // compiled-query loop the seven words of each edge then spill to the stack before the
  // arithmetic (measured: 983 -> 913 instructions per query at d = 8, 1.26x -> 1.17x the raw
  // chain, and a wall-time ratio of 1.5x -> about 1.2x; docs/performance.md).
  // VEX forms when the build targets AVX: a legacy SSE instruction amid VEX code pays for the
  // SSE/AVX state transition (measured with -mavx2: the compiled pose query 12x slower).
  static void LoadWord(Word& out, const std::atomic<Word>& in) noexcept {
#if defined(__AVX__)
    asm volatile("vmovsd %1, %0" : "=x"(out) : "m"(in));
#else
    asm volatile("movsd %1, %0" : "=x"(out) : "m"(in));
#endif
  }
  // Low lane, then high lane: movsd + movhpd, each an atomic 8-byte load, in program order.
  // `token` in and out: the compiler keeps every pair after the header load and before the
  // re-check (HeaderAfter) by data dependency, with no memory clobber, so the pairs stay in
  // registers (a barrier made GCC store them to the stack and load them back).
  static void LoadPair(WordPair& out, const std::atomic<Word>& lo, const std::atomic<Word>& hi,
                       std::uint64_t& token) noexcept {
    WordPair pair;  // a register: an asm output straight into `out` kept arrays in memory
#if defined(__AVX__)
    asm volatile("vmovsd %2, %0\n\tvmovhpd %3, %0, %0"
                 : "=&x"(pair), "+r"(token)
                 : "m"(lo), "m"(hi));
#else
    asm volatile("movsd %2, %0\n\tmovhpd %3, %0" : "=&x"(pair), "+r"(token) : "m"(lo), "m"(hi));
#endif
    out = pair;
  }
  // The header's re-check, after whatever produced `token` (a plain load: x86-TSO keeps it after
  // the word loads).
  [[nodiscard]] std::uint64_t HeaderAfter(std::uint64_t token) const noexcept {
    std::uint64_t h;
    asm volatile("mov %1, %0" : "=r"(h) : "m"(header_), "r"(token));
    return h;
  }
  static void CompilerBarrier() noexcept { asm volatile("" ::: "memory"); }
#else
  // Portable (and ThreadSanitizer-visible) path: acquire loads order the re-check after them.
  static void LoadWord(Word& out, const std::atomic<Word>& in) noexcept {
    out = in.load(std::memory_order_acquire);
  }
  static void LoadPair(WordPair& out, const std::atomic<Word>& lo, const std::atomic<Word>& hi,
                       std::uint64_t& /*token*/) noexcept {
    out = WordPair{lo.load(std::memory_order_acquire), hi.load(std::memory_order_acquire)};
  }
  // After the acquire loads of the words: a relaxed load cannot move before them.
  [[nodiscard]] std::uint64_t HeaderAfter(std::uint64_t /*token*/) const noexcept {
    return header_.load(std::memory_order_relaxed);
  }
  static void CompilerBarrier() noexcept {}
#endif
#undef SEMGRAPH_SEQLOCK_TSAN
  static constexpr std::uint64_t kSeqMask = 0xFFFFFFFFull;
  // The bits LoadWords checks before reading: the epoch and the sequence's odd bit.
  static constexpr std::uint64_t kCheckMask = ~kSeqMask | 1u;
  static constexpr std::uint32_t Epoch(std::uint64_t h) noexcept {
    return static_cast<std::uint32_t>(h >> 32);
  }
  static constexpr std::uint64_t NextSeq(std::uint64_t h) noexcept {
    return (h & ~kSeqMask) | ((h + 1) & kSeqMask);  // the sequence wraps without touching the epoch
  }

  std::atomic<std::uint64_t> header_{0};
  std::atomic<Word> words_[kWords] = {};
};

}  // namespace semgraph::core
