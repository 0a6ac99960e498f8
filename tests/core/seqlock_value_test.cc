// Tests of SeqLockValue (core/include/semgraph/core/seqlock_value.h): bit-exact round trips of
// full and partial payloads, by words, by lane pairs and by selected words to strided places, the
// epoch protocol (Load, LoadWords and LoadWordPairs fail after BumpEpoch, and only then), and
// untorn reads (each way) while a writer thread stores continuously. In non-TSan x86-64
// builds the readers take the inline-assembly path; under ThreadSanitizer the atomic path.
#include "semgraph/core/seqlock_value.h"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <thread>
#include <utility>

namespace semgraph::core {
namespace {

// Seven doubles of payload in a 64-byte type, like the quaternion pose (56 bytes of data).
struct alignas(16) Seven {
  std::array<double, 7> d{};
  double padding = 0;
};
using Value = SeqLockValue<Seven, 7 * sizeof(double)>;

Seven Filled(double x) {
  Seven s;
  s.d.fill(x);
  return s;
}

/// The seven words by LoadWordPairs, as a pose is read: (0, 1), (2, 3), (4, 5), (6, 6).
bool LoadByPairs(const Value& v, std::uint64_t expected_header, Value::Word (&w)[7]) {
  Value::WordPair p[4];
  if (!v.LoadWordPairs(p, std::index_sequence<0, 2, 4, 6>{}, std::index_sequence<1, 3, 5, 6>{},
                       expected_header)) {
    return false;
  }
  for (int i = 0; i < 7; ++i) w[i] = p[i / 2][i % 2];
  return true;
}

TEST(SeqLockValue, OneCacheLinePerValue) {
  EXPECT_EQ(sizeof(Value), 64u);
  EXPECT_EQ(alignof(Value), 64u);
  EXPECT_EQ(Value::kWords, 7u);
}

TEST(SeqLockValue, RoundTripIsBitExact) {
  Seven in;
  in.d = {-0.0,   std::numeric_limits<double>::denorm_min(), 1.0 / 3.0,
          -1e300, std::numeric_limits<double>::max(),        std::nextafter(1.0, 2.0),
          42.0};
  in.padding = 99.0;  // not part of the 56-byte payload: never copied
  Value v(in);
  Seven out = Filled(7.0);
  out.padding = 7.0;
  ASSERT_TRUE(v.Load(out, v.epoch()));
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(out.d[i]), std::bit_cast<std::uint64_t>(in.d[i])) << i;
  }
  EXPECT_EQ(out.padding, 7.0);

  Value::Word words[Value::kWords] = {};
  ASSERT_TRUE(v.LoadWords(words, Value::ExpectedHeader(v.epoch())));
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(words[i]), std::bit_cast<std::uint64_t>(in.d[i])) << i;
  }

  Value::Word by_pairs[Value::kWords] = {};
  ASSERT_TRUE(LoadByPairs(v, Value::ExpectedHeader(v.epoch()), by_pairs));
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(by_pairs[i]), std::bit_cast<std::uint64_t>(in.d[i]))
        << i;
  }
  // Any words in any lanes, a word twice: (6, 0) and (3, 3).
  Value::WordPair p[2];
  ASSERT_TRUE(v.LoadWordPairs(p, std::index_sequence<6, 3>{}, std::index_sequence<0, 3>{},
                              Value::ExpectedHeader(v.epoch())));
  EXPECT_EQ(p[0][0], 42.0);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(p[0][1]), std::bit_cast<std::uint64_t>(-0.0));
  EXPECT_EQ(p[1][0], -1e300);
  EXPECT_EQ(p[1][1], -1e300);
}

TEST(SeqLockValue, StoreReplacesTheWholeValue) {
  Value v(Filled(1.0));
  v.Store(Filled(2.5));
  const Seven out = v.Load();
  for (double x : out.d) EXPECT_EQ(x, 2.5);
}

TEST(SeqLockValue, EpochBumpFailsReadersOfTheOldEpochOnly) {
  Value v(Filled(3.0));
  const std::uint32_t e0 = v.epoch();
  v.BumpEpoch();
  const std::uint32_t e1 = v.epoch();
  EXPECT_EQ(e1, e0 + 1);
  Seven out = Filled(-1.0);
  EXPECT_FALSE(v.Load(out, e0));
  EXPECT_EQ(out.d[0], -1.0);  // untouched on failure
  Value::Word words[Value::kWords] = {};
  EXPECT_FALSE(v.LoadWords(words, Value::ExpectedHeader(e0)));
  ASSERT_TRUE(v.Load(out, e1));
  EXPECT_EQ(out.d[6], 3.0);  // the value survives the bump
  ASSERT_TRUE(v.LoadWords(words, Value::ExpectedHeader(e1)));
  EXPECT_EQ(words[0], 3.0);
  Value::Word by_pairs[Value::kWords] = {};
  EXPECT_FALSE(LoadByPairs(v, Value::ExpectedHeader(e0), by_pairs));
  EXPECT_EQ(by_pairs[0], 0.0);  // untouched on failure
  ASSERT_TRUE(LoadByPairs(v, Value::ExpectedHeader(e1), by_pairs));
  EXPECT_EQ(by_pairs[5], 3.0);
  // Stores never change the epoch.
  for (int i = 0; i < 1000; ++i) v.Store(Filled(i));
  EXPECT_EQ(v.epoch(), e1);
  EXPECT_TRUE(v.LoadWords(words, Value::ExpectedHeader(e1)));
  EXPECT_EQ(words[3], 999.0);
}

TEST(SeqLockValue, CopyKeepsValueAndEpoch) {
  Value v(Filled(5.0));
  v.BumpEpoch();
  const Value copy(v);
  EXPECT_EQ(copy.epoch(), v.epoch());
  EXPECT_EQ(copy.Load().d[2], 5.0);
}

// The writer stores values whose seven words are all equal to a counter; a torn read would
// show two different words. The three read paths are exercised, and the counter a reader sees never
// goes backwards (one writer, reads of one location are coherent).
/// The seven words by LoadSelectedWords, as a covariance record is read into SIMD lanes: words
/// 1 and 6 to `head`, words 0, 2, 3, 4, 5 to every fourth double of `strided`.
void LoadSelected(const Value& v, Value::Word (&w)[7]) {
  Value::Word head[2], strided[5 * 4] = {};
  v.LoadSelectedWords<4>(head, std::index_sequence<1, 6>{}, strided,
                         std::index_sequence<0, 2, 3, 4, 5>{});
  w[1] = head[0];
  w[6] = head[1];
  w[0] = strided[0];
  for (int k = 1; k < 5; ++k) w[k + 1] = strided[4 * k];
}

TEST(SeqLockValue, SelectedWordsGoToTheirPlaces) {
  Seven s;
  for (int i = 0; i < 7; ++i) s.d[static_cast<std::size_t>(i)] = 1.5 * i - 2.0;
  const Value v(s);
  Value::Word w[7];
  LoadSelected(v, w);
  for (int i = 0; i < 7; ++i) EXPECT_EQ(w[i], s.d[static_cast<std::size_t>(i)]) << i;
}

TEST(SeqLockValue, ConcurrentReadersNeverSeeTornValues) {
  Value v(Filled(0.0));
  const std::uint64_t expected = Value::ExpectedHeader(v.epoch());
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    for (int i = 1; !stop.load(std::memory_order_relaxed); ++i) v.Store(Filled(i));
  });
  while (v.Load().d[0] == 0.0) std::this_thread::yield();  // the writer is running
  int torn = 0, backwards = 0, failed = 0;
  double last = 0;
  for (int n = 0; n < 200000; ++n) {
    Value::Word w[Value::kWords] = {};
    if (n % 4 == 0) {
      failed += !v.LoadWords(w, expected);
    } else if (n % 4 == 1) {
      failed += !LoadByPairs(v, expected, w);
    } else if (n % 4 == 2) {
      LoadSelected(v, w);
    } else {
      Seven s;
      failed += !v.Load(s, v.epoch());
      for (int i = 0; i < 7; ++i) w[i] = s.d[i];
    }
    for (int i = 1; i < 7; ++i) torn += w[i] != w[0];
    backwards += w[0] < last;
    last = w[0];
  }
  stop = true;
  writer.join();
  EXPECT_EQ(failed, 0);
  EXPECT_EQ(torn, 0);
  EXPECT_EQ(backwards, 0);
}

}  // namespace
}  // namespace semgraph::core
