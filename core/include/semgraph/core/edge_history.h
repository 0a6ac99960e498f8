// File: semgraph/core/edge_history.h
//
// The sample history of a stamped edge (docs/time.md): SampleHistory<N> keeps up to `capacity`
// samples (stamp + N value words) sorted by stamp in a ring buffer allocated once, when the
// edge becomes stamped (build time). One writer inserts samples while any number of readers
// look up the bracket of a time, lock-free, with a sequence lock over the whole history (as
// SeqLockValue does for one value): a reader never returns a torn sample or a half-shifted
// history, it retries when a write overlapped its read. Every word is a std::atomic (the
// ThreadSanitizer build checks the protocol).
//   PoseHistory   N = 7: the pose (x y z w of the quaternion, then p), 64 bytes per sample
//   TwistHistory  N = 6: (v, w) in [h], 56 bytes per sample
// Covariances (docs/uncertainty.md, "Time"): each sample may carry one (the edge form, 21 words:
// the upper triangle row by row), kept in a parallel array allocated only when the edge is first
// given one (EnsureCovariances, build time), so a history without covariances costs nothing
// more; once allocated it follows every insert and shift (a sample without a covariance stores
// zeros: it counts as zero). Readers ask for them explicitly (Find / Newest with a
// CovarianceBracket), under the same sequence lock as the values.
// Accelerations (docs/dynamics.md, "Stamped accelerations"): a twist history's samples may carry
// one each (7 words: a, alpha in the edge form, then 1 = present / 0 = none), in a second
// parallel array allocated when the edge is first given one (EnsureAccelerations), the same way.
// Both arrays are SideWords below: one implementation of "words beside each sample".
//
// Invariants: 0 < size <= capacity; stamps strictly increasing from the oldest; after every
// insert no sample is older than newest - window. Costs: an in-order insert O(1) (plus the
// samples the window drops); out of order O(samples after it) (a shift); a lookup 2 stamp loads
// when the samples are evenly spaced (a guess, then galloping: O(log size) at worst) + 2 samples
// copied; all noexcept, allocation-free, lock-free.
// Thread safety: one writer (Insert, Restart); readers (Find*, Newest*) concurrent with it.
// Creating and destroying a history needs exclusive access: a graph allocates them at build
// time and frees them only when it is destroyed (HistoryTable below reuses retired ones).
#pragma once

#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "semgraph/core/stable_array.h"
#include "semgraph/core/time.h"

namespace semgraph::core {

/// a - b saturated to int64 (window arithmetic near the ends of the stamp range).
[[nodiscard]] constexpr std::int64_t SaturatingSub(std::int64_t a, std::int64_t b) noexcept {
  std::int64_t r = 0;
  if (__builtin_sub_overflow(a, b, &r)) return b > 0 ? INT64_MIN : INT64_MAX;
  return r;
}

/// Words kept beside every sample of a SampleHistory in a parallel array (covariances,
/// accelerations): null until Ensure (build time, once per history), then following every
/// insert and shift of the samples; a sample stored without such words gets zeros. The array is
/// never freed before its history (readers may hold the pointer); `words_` publishes it
/// (release / acquire). Indexed by the sample's physical ring position.
template <std::size_t W>
class SideWords {
 public:
  [[nodiscard]] bool allocated() const noexcept {
    return words_.load(std::memory_order_relaxed) != nullptr;
  }
  /// Writer, build time: allocates `capacity` zeroed entries once; all or nothing (bad_alloc).
  void Ensure(std::size_t capacity) const {
    if (allocated()) return;
    owned_.reset(new std::atomic<std::uint64_t>[capacity * W]());
    for (std::size_t k = 0; k < capacity * W; ++k) owned_[k].store(0, std::memory_order_relaxed);
    words_.store(owned_.get(), std::memory_order_release);
  }
  /// Writer: entry `at` = c (null: zeros). Nothing when not allocated.
  void Store(std::size_t at, const double* c) noexcept {
    std::atomic<std::uint64_t>* w = owned_.get();
    if (w == nullptr) return;
    for (std::size_t k = 0; k < W; ++k) {
      w[at * W + k].store(std::bit_cast<std::uint64_t>(c == nullptr ? 0.0 : c[k]),
                          std::memory_order_release);
    }
  }
  /// Writer: entry `to` = entry `from`.
  void Copy(std::size_t from, std::size_t to) noexcept {
    std::atomic<std::uint64_t>* w = owned_.get();
    if (w == nullptr) return;
    for (std::size_t k = 0; k < W; ++k) {
      w[to * W + k].store(w[from * W + k].load(std::memory_order_relaxed),
                          std::memory_order_release);
    }
  }
  /// Writer: entry `at` (zeros when not allocated).
  void WriterLoad(std::size_t at, double (&c)[W]) const noexcept {
    const std::atomic<std::uint64_t>* w = owned_.get();
    for (std::size_t k = 0; k < W; ++k) {
      c[k] =
          w == nullptr ? 0.0 : std::bit_cast<double>(w[at * W + k].load(std::memory_order_relaxed));
    }
  }
  /// Reader (under the history's sequence lock): entries i0 (and i1 when `both`); false when
  /// not allocated (nothing loaded).
  bool Load(std::size_t i0, std::size_t i1, bool both, double (&c0)[W],
            double (&c1)[W]) const noexcept {
    const std::atomic<std::uint64_t>* w = words_.load(std::memory_order_acquire);
    if (w == nullptr) return false;
    LoadOne(w + i0 * W, c0);
    if (both) LoadOne(w + i1 * W, c1);
    return true;
  }

 private:
  static void LoadOne(const std::atomic<std::uint64_t>* w, double (&c)[W]) noexcept {
    for (std::size_t k = 0; k < W; ++k) {
      c[k] = std::bit_cast<double>(w[k].load(std::memory_order_acquire));
    }
  }
  mutable std::unique_ptr<std::atomic<std::uint64_t>[]> owned_;
  mutable std::atomic<const std::atomic<std::uint64_t>*> words_{nullptr};
};

/// The side words of a Bracket's samples (`any` false: the history has none: zeros).
template <std::size_t W>
struct SideBracket {
  bool any = false;
  double c0[W], c1[W];  ///< c1 only where the Bracket's v1 is
};

template <std::size_t N>
class SampleHistory {
 public:
  static constexpr std::size_t kValueWords = N;
  static constexpr std::size_t kSampleWords = N + 1;
  using Values = double[N];
  static constexpr std::size_t kCovarianceWords = 21;  ///< upper triangle of a 6x6, row by row
  using CovarianceWords = double[kCovarianceWords];
  /// a (3), alpha (3), present (1 or 0): an acceleration in the edge form (twist histories).
  static constexpr std::size_t kAccelerationWords = 7;

  /// The covariances of a Bracket's samples (`any` false: the edge has none, they are zero).
  using CovarianceBracket = SideBracket<kCovarianceWords>;
  /// The accelerations of a Bracket's samples (`any` false: none was ever given).
  using AccelerationBracket = SideBracket<kAccelerationWords>;

  /// Allocates capacity samples (>= 2).
  explicit SampleHistory(std::size_t capacity)
      : capacity_(static_cast<std::uint32_t>(capacity < 2 ? 2 : capacity)),
        words_(new std::atomic<std::uint64_t>[capacity_ * kSampleWords]) {}

  [[nodiscard]] std::uint32_t capacity() const noexcept { return capacity_; }
  [[nodiscard]] static constexpr std::size_t BytesPerSample() noexcept { return kSampleWords * 8; }

  /// What a reader sees of time t: the bracket s0 <= t <= s1 (s0 == s1 when t is a stamp or
  /// the history holds one sample at t), or t before the first / after the last sample.
  struct Bracket {
    enum class Where : std::uint8_t { kInside, kBefore, kAfter } where = Where::kInside;
    std::int64_t s0 = 0,
                 s1 = 0;  ///< kInside: the bracket; kBefore/kAfter: the nearest sample (s0 = s1)
    std::int64_t first = 0, last = 0;  ///< the whole range
    double v0[N], v1[N];  ///< at s0 (but not set by a false FindSegment), at s1 (unless exact)
    bool exact = false;   ///< t equals s0 (only v0 is meaningful)
  };

  /// The bracket of t. Lock-free; retries only while a write overlaps.
  /// With `cov` / `acc`: the covariances / accelerations of the same samples too.
  void Find(std::int64_t t, Bracket& out, CovarianceBracket* cov = nullptr,
            AccelerationBracket* acc = nullptr) const noexcept {
    ReadLocked([&](const Ring& r, std::uint32_t n) noexcept {
      std::uint32_t i0 = 0;
      out.first = r.Stamp(0);
      out.last = r.Stamp(n - 1);
      if (t <= out.first) {
        out.where = t == out.first ? Bracket::Where::kInside : Bracket::Where::kBefore;
        out.s0 = out.s1 = out.first;
        out.exact = true;
        r.Load(0, out.v0);
      } else if (t >= out.last) {
        out.where = t == out.last ? Bracket::Where::kInside : Bracket::Where::kAfter;
        out.s0 = out.s1 = out.last;
        out.exact = true;
        r.Load(n - 1, out.v0);
        i0 = n - 1;
      } else {
        const std::uint32_t lo = FirstAfter(r, n, out.first, out.last, t);
        i0 = lo - 1;
        out.where = Bracket::Where::kInside;
        out.s0 = r.Stamp(lo - 1);
        out.exact = out.s0 == t;
        out.s1 = r.Stamp(lo);
        r.Load(lo - 1, out.v0);
        r.Load(lo, out.v1);
      }
      LoadSides(r, i0, !out.exact, cov, acc);
    });
  }

  /// The segment a derivative at t uses: [s_i, s_i+1] containing t, the one after t when t is a
  /// stamp, the last one at the newest stamp. False when t is outside the samples or there is
  /// one sample. With `cov`: the covariances of the segment's two samples (c0, c1).
  [[nodiscard]] bool FindSegment(std::int64_t t, Bracket& out,
                                 CovarianceBracket* cov = nullptr) const noexcept {
    bool ok = false;
    ReadLocked([&](const Ring& r, std::uint32_t n) noexcept {
      out.first = r.Stamp(0);
      out.last = r.Stamp(n - 1);
      ok = n >= 2 && t >= out.first && t <= out.last;
      if (ok) {
        // The first index with stamp > t, or n - 1 at the newest.
        const std::uint32_t lo = t == out.last ? n - 1 : FirstAfter(r, n, out.first, out.last, t);
        out.where = Bracket::Where::kInside;
        out.s0 = r.Stamp(lo - 1);
        out.s1 = r.Stamp(lo);
        out.exact = false;
        r.Load(lo - 1, out.v0);
        r.Load(lo, out.v1);
        LoadSides(r, lo - 1, true, cov, nullptr);
      } else {
        out.where = t < out.first ? Bracket::Where::kBefore : Bracket::Where::kAfter;
      }
    });
    return ok;
  }

  /// The newest sample (stamp and value), with its covariance / acceleration (in c0) when
  /// `cov` / `acc`.
  void Newest(std::int64_t& stamp, double (&v)[N], std::int64_t& first,
              CovarianceBracket* cov = nullptr, AccelerationBracket* acc = nullptr) const noexcept {
    ReadLocked([&](const Ring& r, std::uint32_t n) noexcept {
      stamp = r.Stamp(n - 1);
      first = r.Stamp(0);
      r.Load(n - 1, v);
      LoadSides(r, n - 1, false, cov, acc);
    });
  }
  /// The newest stamp only.
  [[nodiscard]] std::int64_t NewestStamp() const noexcept {
    std::int64_t s = 0;
    ReadLocked([&](const Ring& r, std::uint32_t n) noexcept { s = r.Stamp(n - 1); });
    return s;
  }

  // ---------------------------------------------------------------- the writer's side
  // The writer reads without the lock (it is the only one changing the history).

  [[nodiscard]] std::uint32_t size() const noexcept {
    return size_.load(std::memory_order_relaxed);
  }
  [[nodiscard]] std::int64_t newest_stamp() const noexcept { return Stamp(head(), size() - 1); }
  [[nodiscard]] std::int64_t oldest_stamp() const noexcept { return Stamp(head(), 0); }
  /// True once the edge was given a covariance (its samples then carry one each).
  [[nodiscard]] bool has_covariances() const noexcept { return cov_.allocated(); }
  /// True once the edge was given an acceleration (twist histories).
  [[nodiscard]] bool has_accelerations() const noexcept { return acc_.allocated(); }
  /// Writer, build time: the covariance array (zeros: every sample so far counts as exact).
  /// Allocates once per history (a reused history keeps it); all or nothing (std::bad_alloc).
  /// const (the array is `mutable`): reserved by the graph's const handle finders too, as the
  /// untimed covariance records are (edge_values.h).
  void EnsureCovariances() const { cov_.Ensure(capacity_); }
  /// Writer, build time: the acceleration array (every sample so far: none), as covariances.
  void EnsureAccelerations() const { acc_.Ensure(capacity_); }
  /// The covariance stored at exactly `stamp` (zeros when the edge has none); false when no
  /// sample has that stamp. Writer.
  [[nodiscard]] bool CovarianceAt(std::int64_t stamp,
                                  double (&c)[kCovarianceWords]) const noexcept {
    const std::uint32_t i = LowerBound(stamp);
    if (i >= size() || Stamp(head(), i) != stamp) return false;
    cov_.WriterLoad(Sample(head(), i), c);
    return true;
  }
  /// The acceleration words stored at exactly `stamp` (zeros, i.e. none, when the history has
  /// no acceleration array); false when no sample has that stamp. Writer.
  [[nodiscard]] bool AccelerationAt(std::int64_t stamp,
                                    double (&a)[kAccelerationWords]) const noexcept {
    const std::uint32_t i = LowerBound(stamp);
    if (i >= size() || Stamp(head(), i) != stamp) return false;
    acc_.WriterLoad(Sample(head(), i), a);
    return true;
  }
  /// Writer: the acceleration words of the sample at exactly `stamp` become `a` (the array
  /// exists: EnsureAccelerations), under the sequence lock; false (nothing written) when no
  /// sample has that stamp.
  bool SetAccelerationAt(std::int64_t stamp, const double (&a)[kAccelerationWords]) noexcept {
    const std::uint32_t i = LowerBound(stamp);
    if (i >= size() || Stamp(head(), i) != stamp) return false;
    const std::uint64_t h = seq_.load(std::memory_order_relaxed);
    seq_.store(h + 1, std::memory_order_relaxed);  // odd; ordered before the release stores
    acc_.Store(Sample(head(), i), a);
    seq_.store(h + 2, std::memory_order_release);
    return true;
  }

  /// The value stored at exactly `stamp`, if any.
  [[nodiscard]] bool ValueAt(std::int64_t stamp, double (&v)[N]) const noexcept {
    const std::uint32_t i = LowerBound(stamp);
    if (i >= size() || Stamp(head(), i) != stamp) return false;
    LoadValues(head(), i, v);
    return true;
  }

  /// Drops every sample and holds (stamp, v) alone: one write under the sequence lock, so a
  /// reader overlapping it retries, and one after it sees only the new sample (a retired
  /// history reused for another edge: HistoryTable::Install).
  /// `c`, `a`: the sample's covariance and acceleration words (null: none; zeros if the
  /// history has the array).
  void Restart(std::int64_t stamp, const double (&v)[N], const double* c = nullptr,
               const double* a = nullptr) noexcept {
    const std::uint64_t h = seq_.load(std::memory_order_relaxed);
    seq_.store(h + 1, std::memory_order_relaxed);  // odd; ordered before the release stores below
    StoreValues(0, 0, stamp, v);
    StoreSides(0, 0, c, a);
    head_.store(0, std::memory_order_release);
    size_.store(1, std::memory_order_release);
    seq_.store(h + 2, std::memory_order_release);
  }

  /// Inserts (or replaces the value at an equal stamp), then drops the oldest sample when full
  /// and every sample older than newest - window. The caller checked stamp_too_old and the
  /// duplicate policy. A sample older than all while the history is full is dropped at once.
  /// `c`, `a`: the sample's covariance and acceleration words (null: none; stored as zeros
  /// once the array exists, which a non-null one needs: EnsureCovariances, EnsureAccelerations).
  void Insert(std::int64_t stamp, const double (&v)[N], std::int64_t window_ns,
              const double* c = nullptr, const double* a = nullptr) noexcept {
    const std::uint64_t h = seq_.load(std::memory_order_relaxed);
    seq_.store(h + 1, std::memory_order_relaxed);  // odd: a write is in progress
    std::uint32_t n = size(), head = this->head();
    // In order (the common case) the new sample goes last: no search.
    std::uint32_t pos = n > 0 && stamp > Stamp(head, n - 1) ? n : LowerBound(stamp);
    if (pos < n && Stamp(head, pos) == stamp) {
      StoreValues(head, pos, stamp, v);
      StoreSides(head, pos, c, a);
    } else if (!(n == capacity_ && pos == 0)) {
      if (n == capacity_) {  // full: drop the oldest
        head = Next(head);
        --n;
        --pos;
      }
      for (std::uint32_t i = n; i > pos; --i) CopySample(head, i - 1, i);  // shift the later ones
      StoreValues(head, pos, stamp, v);
      StoreSides(head, pos, c, a);
      ++n;
    }
    const std::int64_t keep_from = SaturatingSub(Stamp(head, n - 1), window_ns);
    while (n > 1 && Stamp(head, 0) < keep_from) {
      head = Next(head);
      --n;
    }
    head_.store(head, std::memory_order_release);
    size_.store(n, std::memory_order_release);
    seq_.store(h + 2, std::memory_order_release);
  }

 private:
  std::uint32_t head() const noexcept { return head_.load(std::memory_order_relaxed); }
  std::uint32_t Next(std::uint32_t i) const noexcept { return i + 1 == capacity_ ? 0 : i + 1; }

  /// The samples as one read sees them: the array, capacity and head held in registers (every
  /// acquire load orders the loads after it, so members would be loaded again for each word).
  struct Ring {
    const std::atomic<std::uint64_t>* words;
    std::uint32_t capacity, head;
    /// In bounds for head < capacity and i < capacity, even from a torn read (ReadLocked
    /// checks both: head is stored < capacity, and i < n <= capacity).
    std::size_t Slot(std::uint32_t i) const noexcept {
      const std::uint32_t s = head + i;
      return static_cast<std::size_t>(s >= capacity ? s - capacity : s) * kSampleWords;
    }
    std::int64_t Stamp(std::uint32_t i) const noexcept {
      return static_cast<std::int64_t>(words[Slot(i)].load(std::memory_order_acquire));
    }
    void Load(std::uint32_t i, double (&v)[N]) const noexcept {
      const std::atomic<std::uint64_t>* w = words + Slot(i) + 1;
      [&]<std::size_t... k>(std::index_sequence<k...>) {  // unrolled: 2 instructions a word
        ((v[k] = std::bit_cast<double>(w[k].load(std::memory_order_acquire))), ...);
      }
      (std::make_index_sequence<N>{});
    }
  };
  Ring ring(std::uint32_t head) const noexcept { return Ring{words_.get(), capacity_, head}; }

  /// One read under the sequence lock: f(ring, size) on a consistent snapshot of the header,
  /// again until no write overlapped it (f writes only its caller's variables).
  template <class F>
  [[gnu::always_inline]] void ReadLocked(F&& f) const noexcept {
    const std::atomic<std::uint64_t>* const words = words_.get();
    const std::uint32_t capacity = capacity_;
    for (;;) {
      const std::uint64_t h1 = seq_.load(std::memory_order_acquire);
      if (h1 & 1u) continue;
      const std::uint32_t n = size_.load(std::memory_order_acquire),
                          head = head_.load(std::memory_order_acquire);
      // Never for a history in use (it has a sample, and head < capacity); a torn read retries.
      if (n == 0 || n > capacity || head >= capacity) continue;
      f(Ring{words, capacity, head}, n);
      if (seq_.load(std::memory_order_relaxed) == h1) return;
    }
  }

  std::size_t Slot(std::uint32_t head, std::uint32_t i) const noexcept {
    return ring(head).Slot(i);
  }
  std::int64_t Stamp(std::uint32_t head, std::uint32_t i) const noexcept {
    return ring(head).Stamp(i);
  }
  void LoadValues(std::uint32_t head, std::uint32_t i, double (&v)[N]) const noexcept {
    ring(head).Load(i, v);
  }
  /// The first index with stamp > t, in [1, n - 1], for first <= t < last (the stamps of
  /// indices 0 and n - 1; n >= 2). Samples usually come at a steady rate, so the search starts
  /// where t falls if they were evenly spaced (one division), then gallops away from that guess
  /// (steps 1, 2, 4, ...) until it brackets the answer, then bisects the bracket: 2 stamp loads
  /// when the guess is right, O(log distance) when it is not, O(log n) at worst. Under a torn
  /// read (the stamps not sorted) the loops still end and the answer is clamped to [1, n - 1];
  /// the caller's sequence check discards it.
  static std::uint32_t FirstAfter(const Ring& r, std::uint32_t n, std::int64_t first,
                                  std::int64_t last, std::int64_t t) noexcept {
    const double f =
        static_cast<double>(static_cast<std::uint64_t>(t) - static_cast<std::uint64_t>(first)) /
        static_cast<double>(static_cast<std::uint64_t>(last) - static_cast<std::uint64_t>(first));
    std::uint32_t lo = 1, hi = n - 1;
    // f in [0, 1) (first <= t < last; rounding may give 1): the guess is in [1, n - 1].
    std::uint32_t g = static_cast<std::uint32_t>(f * static_cast<double>(n - 1)) + 1;
    if (g > hi) g = hi;
    if (r.Stamp(g) > t) {  // the answer is in [lo, g]: gallop down from g - 1
      hi = g;
      for (std::uint32_t step = 1; hi - lo >= step; step *= 2) {
        const std::uint32_t k = hi - step;
        if (r.Stamp(k) <= t) {
          lo = k + 1;
          break;
        }
        hi = k;
      }
    } else {  // the answer is in [g + 1, hi]: gallop up from g + 1
      lo = g + 1;
      for (std::uint32_t step = 1; lo < hi; step *= 2) {
        const std::uint32_t k = hi - lo >= step ? lo + step - 1 : hi;
        if (r.Stamp(k) > t) {
          hi = k;
          break;
        }
        lo = k + 1;
      }
    }
    while (lo < hi) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      if (r.Stamp(mid) > t)
        hi = mid;
      else
        lo = mid + 1;
    }
    return lo < n - 1 ? lo : n - 1;
  }
  void StoreValues(std::uint32_t head, std::uint32_t i, std::int64_t stamp,
                   const double (&v)[N]) noexcept {
    const std::size_t s = Slot(head, i);
    words_[s].store(static_cast<std::uint64_t>(stamp), std::memory_order_release);
    for (std::size_t k = 0; k < N; ++k)
      words_[s + 1 + k].store(std::bit_cast<std::uint64_t>(v[k]), std::memory_order_release);
  }
  void CopySample(std::uint32_t head, std::uint32_t from, std::uint32_t to) noexcept {
    const std::size_t a = Slot(head, from), b = Slot(head, to);
    for (std::size_t k = 0; k < kSampleWords; ++k) {
      words_[b + k].store(words_[a + k].load(std::memory_order_relaxed), std::memory_order_release);
    }
    cov_.Copy(Sample(head, from), Sample(head, to));
    acc_.Copy(Sample(head, from), Sample(head, to));
  }
  /// The physical ring position of sample i (the side arrays' index).
  std::size_t Sample(std::uint32_t head, std::uint32_t i) const noexcept {
    return Slot(head, i) / kSampleWords;
  }
  void StoreSides(std::uint32_t head, std::uint32_t i, const double* c, const double* a) noexcept {
    cov_.Store(Sample(head, i), c);
    acc_.Store(Sample(head, i), a);
  }
  /// Reader: the side words of samples i (and i + 1 when `both`) asked for.
  void LoadSides(const Ring& r, std::uint32_t i, bool both, CovarianceBracket* cov,
                 AccelerationBracket* acc) const noexcept {
    const std::size_t i0 = r.Slot(i) / kSampleWords, i1 = both ? r.Slot(i + 1) / kSampleWords : 0;
    if (cov != nullptr) cov->any = cov_.Load(i0, i1, both, cov->c0, cov->c1);
    if (acc != nullptr) acc->any = acc_.Load(i0, i1, both, acc->c0, acc->c1);
  }
  // Writer only: the first index whose stamp is >= stamp.
  std::uint32_t LowerBound(std::int64_t stamp) const noexcept {
    std::uint32_t lo = 0, hi = size();
    const std::uint32_t h = head();
    while (lo < hi) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      if (Stamp(h, mid) < stamp)
        lo = mid + 1;
      else
        hi = mid;
    }
    return lo;
  }

  std::atomic<std::uint64_t> seq_{0};
  std::atomic<std::uint32_t> head_{0}, size_{0};
  std::uint32_t capacity_;
  std::unique_ptr<std::atomic<std::uint64_t>[]> words_;
  SideWords<kCovarianceWords> cov_;    ///< until EnsureCovariances: none
  SideWords<kAccelerationWords> acc_;  ///< until EnsureAccelerations: none
};

/// Writer: whether the acceleration stored with h's sample at s equals the words a (null: none),
/// each vector within 1e-6 max(1, |stored|) as the twists of the duplicate-stamp rule. True
/// for no sample at s only when a is null.
template <class History>
[[nodiscard]] bool SameSampleAcceleration(const History& h, std::int64_t s,
                                          const double* a) noexcept {
  double stored[History::kAccelerationWords];
  if (!h.AccelerationAt(s, stored)) return a == nullptr;
  if ((stored[6] != 0.0) != (a != nullptr)) return false;
  if (a == nullptr) return true;
  const auto close = [&](int k) {
    double d2 = 0, n2 = 0;
    for (int i = k; i < k + 3; ++i) {
      d2 += (stored[i] - a[i]) * (stored[i] - a[i]);
      n2 += stored[i] * stored[i];
    }
    return d2 <= 1e-12 * (n2 > 1.0 ? n2 : 1.0);
  };
  return close(0) && close(3);
}

using PoseHistory = SampleHistory<7>;   ///< quaternion x y z w, then p
using TwistHistory = SampleHistory<6>;  ///< v, then w, both in [h]
static_assert(PoseHistory::BytesPerSample() == 64);

/// The histories of one kind of stamped edge (pose edges by head frame, twist edges by slot),
/// made so that readers may keep evaluating compiled queries while the writer adds and removes
/// stamped edges (docs/realtime.md, "Topology changes while readers run"):
///   - the table of history pointers is a StableArray of atomics (one per frame / twist slot,
///     grown with the edge values, never moved), stored with release, loaded with acquire;
///   - a history is never freed while the graph lives: removing an edge retires its history
///     into a free list, and the next new history of the same capacity reuses it (Restart
///     resets it through its own sequence lock). So a loop that removes and re-adds stamped
///     edges reaches a steady state without allocation, and memory is bounded: the histories
///     ever allocated number at most the peak count of edges stamped at once (plus those one
///     build operation holds before installing them), each sizeof(H) + capacity samples.
/// The reader's side of the protocol (timed_read.h, evaluate.h FlatSource): a compiled query
/// checks its edge's epoch, loads the pointer, reads the history under its sequence lock, then
/// checks the epoch again. The writer removes an edge by bumping its epoch (release), then
/// retiring the history (pointer store nullptr, release); a reuse rewrites it later, every word
/// stored with release. A reader that loaded anything the writer stored after the bump (the
/// nullptr, a word or header of the reset history, the pointer of a new history) synchronizes
/// with that store, so its second epoch load sees the bump: it reports kQueryInvalidated rather
/// than numbers of another edge. A reader that saw none of it read the old history, whole (the
/// sequence lock): an answer of the graph before the change.
/// Invariants: of(i) is null or a history with >= 1 sample; owned_ holds every history allocated,
/// free_ those not installed, free_.capacity() >= owned_.size() (so Retire never allocates).
/// Costs: of() one acquire load after the StableArray index; New O(free histories) and an
/// allocation only when none fits; Install/Retire O(1), noexcept.
/// Thread safety: one writer (Grow, Reserve, New, Install, Retire, writable); of() from any
/// thread, for an index that existed when the reader learned of it.
template <class H>
class HistoryTable {
 public:
  /// Gives a history back to the free list unless installed (a build operation that fails after
  /// New changes nothing). Never allocates (free_ has room for every history).
  struct Return {
    std::vector<H*>* free = nullptr;
    void operator()(H* h) const noexcept { free->push_back(h); }
  };
  using Lease = std::unique_ptr<H, Return>;

  /// The history of edge i, or nullptr (timeless). Any thread (acquire: the history's first
  /// sample, written before the pointer was stored, is visible).
  [[nodiscard]] const H* of(std::size_t i) const noexcept {
    return table_[i].load(std::memory_order_acquire);
  }
  /// The writer's history of edge i (stamped: not null).
  [[nodiscard]] H& writable(std::size_t i) noexcept {
    return *table_[i].load(std::memory_order_relaxed);
  }

  /// Room for n entries (all or nothing); then Grow up to n does not allocate.
  void Reserve(std::size_t n) { table_.Reserve(n); }
  /// At least n entries (new ones null).
  void Grow(std::size_t n) {
    if (table_.size() < n) table_.Resize(n);
  }

  /// A history of `capacity` samples: a retired one if any fits, else a new one. Allocates only
  /// then; all or nothing under std::bad_alloc.
  [[nodiscard]] Lease New(std::size_t capacity) {
    const std::size_t cap = capacity < 2 ? 2 : capacity;
    for (std::size_t k = free_.size(); k-- > 0;) {
      if (free_[k]->capacity() == cap) {
        H* h = free_[k];
        free_.erase(free_.begin() + static_cast<std::ptrdiff_t>(k));
        return Lease(h, Return{&free_});
      }
    }
    owned_.reserve(owned_.size() + 1);
    free_.reserve(owned_.size() + 1);
    owned_.push_back(std::make_unique<H>(cap));  // no reallocation: reserved
    return Lease(owned_.back().get(), Return{&free_});
  }
  /// Makes `h` edge i's history, holding the one sample (stamp, v) (a reused history loses its
  /// old samples through its sequence lock), then publishes it (release).
  void Install(std::size_t i, Lease h, std::int64_t stamp, const double (&v)[H::kValueWords],
               const double* c = nullptr, const double* a = nullptr) noexcept {
    H* p = h.release();
    p->Restart(stamp, v, c, a);
    table_[i].store(p, std::memory_order_release);
  }
  /// Edge i becomes timeless (its edge was removed: the caller bumped the epoch before); its
  /// history goes to the free list, untouched until reused (readers may still be reading it).
  void Retire(std::size_t i) noexcept {
    if (i >= table_.size()) return;
    H* p = table_[i].load(std::memory_order_relaxed);
    if (p == nullptr) return;
    table_[i].store(nullptr, std::memory_order_release);
    free_.push_back(p);  // capacity >= owned_.size(): no allocation
  }

  /// Histories allocated / retired and waiting for reuse.
  [[nodiscard]] std::size_t allocated() const noexcept { return owned_.size(); }
  [[nodiscard]] std::size_t retired() const noexcept { return free_.size(); }
  [[nodiscard]] std::size_t ApproximateBytes() const noexcept {
    std::size_t bytes =
        table_.bytes() + owned_.capacity() * sizeof(void*) + free_.capacity() * sizeof(void*);
    for (const auto& h : owned_) {
      bytes += sizeof(H) + h->capacity() * H::BytesPerSample();
      if (h->has_covariances()) bytes += h->capacity() * H::kCovarianceWords * 8;
      if (h->has_accelerations()) bytes += h->capacity() * H::kAccelerationWords * 8;
    }
    return bytes;
  }

 private:
  StableArray<std::atomic<H*>> table_;
  std::vector<std::unique_ptr<H>> owned_;
  std::vector<H*> free_;
};

using PoseHistoryLease = HistoryTable<PoseHistory>::Lease;
using TwistHistoryLease = HistoryTable<TwistHistory>::Lease;

/// The histories of a graph's stamped edges: by frame (the pose edge into it) and by twist edge
/// slot; nullptr for a timeless (or constant) edge. The tables grow with the edge values
/// (EdgeValues::AddFrame / AddTwistSlot), so every frame and slot a reader knows has an entry.
struct EdgeHistories {
  TimeOptions options;  ///< the graph's (validated when the graph is made; fixed after)
  HistoryTable<PoseHistory> pose;
  HistoryTable<TwistHistory> twist;

  /// Any thread, for a frame / slot of the graph.
  [[nodiscard]] const PoseHistory* pose_of(std::uint32_t frame) const noexcept {
    return pose.of(frame);
  }
  [[nodiscard]] const TwistHistory* twist_of(std::uint32_t slot) const noexcept {
    return twist.of(slot);
  }
  [[nodiscard]] std::size_t ApproximateBytes() const noexcept {
    return pose.ApproximateBytes() + twist.ApproximateBytes();
  }
};

}  // namespace semgraph::core
