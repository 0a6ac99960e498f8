// core/edge_history.h: the bracket search (a guess from even spacing, galloping, bisection)
// against a linear scan of the stamps the test inserted, for evenly spaced, jittered, clustered
// and sparse stamps, with the ring wrapped by the window and by the capacity.
#include "semgraph/core/edge_history.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace semgraph::core {
namespace {

// Stamps kept: the last `capacity` inserted (in order) that are within the window of the newest.
std::vector<std::int64_t> Kept(const std::vector<std::int64_t>& all, std::size_t capacity,
                               std::int64_t window) {
  std::vector<std::int64_t> kept(all.end() - std::min(all.size(), capacity), all.end());
  kept.erase(kept.begin(), std::lower_bound(kept.begin(), kept.end(), kept.back() - window));
  return kept;
}

void CheckAgainstScan(const PoseHistory& h, const std::vector<std::int64_t>& kept, std::int64_t t) {
  PoseHistory::Bracket b;
  h.Find(t, b);
  ASSERT_EQ(b.first, kept.front());
  ASSERT_EQ(b.last, kept.back());
  if (t < kept.front() || t > kept.back()) {
    EXPECT_NE(b.where, PoseHistory::Bracket::Where::kInside) << t;
    return;
  }
  ASSERT_EQ(b.where, PoseHistory::Bracket::Where::kInside) << t;
  // The scan: the last stamp <= t, and the next one.
  std::size_t i = 0;
  while (i + 1 < kept.size() && kept[i + 1] <= t) ++i;
  EXPECT_EQ(b.s0, kept[i]) << t;
  EXPECT_EQ(b.exact, kept[i] == t) << t;
  if (!b.exact) {
    EXPECT_EQ(b.s1, kept[i + 1]) << t;
    EXPECT_EQ(b.v1[4], static_cast<double>(kept[i + 1])) << t;  // the sample stores its stamp
  }
  EXPECT_EQ(b.v0[4], static_cast<double>(kept[i])) << t;
  PoseHistory::Bracket seg;
  if (kept.size() >= 2 && h.FindSegment(t, seg)) {
    const std::size_t j = std::min(i, kept.size() - 2);  // the last segment at the newest stamp
    EXPECT_EQ(seg.s0, kept[j]) << t;
    EXPECT_EQ(seg.s1, kept[j + 1]) << t;
  }
}

TEST(EdgeHistoryTest, BracketSearchMatchesALinearScan) {
  std::mt19937_64 rng(5);
  enum class Spacing { kEven, kJitter, kClustered, kSparse };
  for (Spacing spacing :
       {Spacing::kEven, Spacing::kJitter, Spacing::kClustered, Spacing::kSparse}) {
    for (std::size_t capacity : {2u, 3u, 17u, 256u}) {
      const std::int64_t window = 500'000;
      PoseHistory h(capacity);
      std::vector<std::int64_t> all;
      std::int64_t s = 1'000;
      for (int k = 0; k < 600; ++k) {
        switch (spacing) {
          case Spacing::kEven:
            s += 1'000;
            break;
          case Spacing::kJitter:
            s += 900 + static_cast<std::int64_t>(rng() % 200);
            break;
          case Spacing::kClustered:
            s += k % 10 == 0 ? 20'000 : 1 + rng() % 3;
            break;
          case Spacing::kSparse:
            s += 1 + static_cast<std::int64_t>(rng() % 40'000);
            break;
        }
        const double v[7] = {0, 0, 0, 1, static_cast<double>(s), 0, 0};
        if (all.empty()) {
          h.Restart(s, v);
        } else {
          h.Insert(s, v, window);
        }
        all.push_back(s);
        if (k % 37 != 0 && k != 599) continue;
        const std::vector<std::int64_t> kept = Kept(all, capacity, window);
        ASSERT_EQ(h.size(), kept.size());
        for (std::int64_t x : kept) {
          CheckAgainstScan(h, kept, x);
          CheckAgainstScan(h, kept, x + 1);
          CheckAgainstScan(h, kept, x - 1);
        }
        for (int q = 0; q < 200; ++q) {
          const auto span = static_cast<std::uint64_t>(kept.back() - kept.front() + 2'000);
          CheckAgainstScan(h, kept, kept.front() - 1'000 + static_cast<std::int64_t>(rng() % span));
        }
      }
    }
  }
}

}  // namespace
}  // namespace semgraph::core
