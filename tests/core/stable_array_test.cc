// StableArray (core/include/semgraph/core/stable_array.h): elements keep their addresses while
// the array grows across many blocks and when it is moved; indices map to the right elements
// across block boundaries; Reserve allocates whole blocks and nothing below capacity.
#include "semgraph/core/stable_array.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace semgraph::core {
namespace {

struct alignas(64) Wide {
  std::uint64_t value = 0;
  Wide() = default;
  explicit Wide(std::uint64_t v) : value(v) {}
};

TEST(StableArray, ElementsNeverMoveWhileItGrowsAndIndicesCrossBlocks) {
  StableArray<Wide> a;
  EXPECT_EQ(a.size(), 0u);
  EXPECT_EQ(a.capacity(), 0u);
  std::vector<const Wide*> address;
  constexpr std::uint64_t kN = 20000;  // blocks of 64, 128, ..., 16384: nine blocks
  for (std::uint64_t i = 0; i < kN; ++i) {
    const Wide& w = a.EmplaceBack(i * 7 + 1);
    address.push_back(&w);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(&w) % 64, 0u);
  }
  ASSERT_EQ(a.size(), kN);
  EXPECT_EQ(a.capacity(), 64u * ((1u << 9) - 1));  // 32,704: the smallest block count holding kN
  for (std::uint64_t i = 0; i < kN; ++i) {
    ASSERT_EQ(&a[i], address[i]) << i;  // never moved by the growth after it
    ASSERT_EQ(a[i].value, i * 7 + 1) << i;
  }
  // Consecutive within a block, a new block at 64, 192, 448, ... (64 * (2^k - 1)).
  EXPECT_EQ(&a[62] + 1, &a[63]);
  EXPECT_EQ(&a[64] + 127, &a[191]);
  EXPECT_EQ(&a[192] + 255, &a[447]);

  const StableArray<Wide>& c = a;
  EXPECT_EQ(&c[12345], address[12345]);

  // A move hands the blocks over: the same addresses, the source empty.
  StableArray<Wide> b(std::move(a));
  EXPECT_EQ(b.size(), kN);
  EXPECT_EQ(&b[19999], address[19999]);
  EXPECT_EQ(a.size(), 0u);  // NOLINT(bugprone-use-after-move): the documented moved-from state
  EXPECT_EQ(a.capacity(), 0u);
}

TEST(StableArray, ReserveAllocatesWholeBlocksAndResizeDefaultConstructs) {
  StableArray<Wide> a;
  a.Reserve(1);
  EXPECT_EQ(a.capacity(), 64u);
  a.Reserve(65);
  EXPECT_EQ(a.capacity(), 192u);
  a.Reserve(100);  // below capacity: nothing
  EXPECT_EQ(a.capacity(), 192u);
  EXPECT_EQ(a.bytes(), 192u * sizeof(Wide));
  a.Resize(70);
  EXPECT_EQ(a.size(), 70u);
  for (std::size_t i = 0; i < 70; ++i) EXPECT_EQ(a[i].value, 0u);
  a[69].value = 5;
  a.Resize(10);  // never shrinks
  EXPECT_EQ(a.size(), 70u);
  EXPECT_EQ(a[69].value, 5u);
  a.EmplaceBack(9);
  EXPECT_EQ(a[70].value, 9u);
}

}  // namespace
}  // namespace semgraph::core
