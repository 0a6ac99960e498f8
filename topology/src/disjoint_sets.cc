#include "semgraph/topology/disjoint_sets.h"

#include <algorithm>
#include <limits>
#include <utility>

#include "semgraph/base/demand.h"

namespace semgraph::topology {

void DisjointSets::Reserve(std::size_t n) {
  // Geometric growth, so that reserving one more element at a time stays O(1) amortized.
  const std::size_t capacity = std::min(link_.capacity(), size_.capacity());
  if (n <= capacity) return;
  n = std::max(n, 2 * capacity);
  link_.reserve(n);
  size_.reserve(n);
}

std::uint32_t DisjointSets::AddElement() {
  const std::size_t n = size();
  SEMGRAPH_DEMAND(n < std::numeric_limits<std::uint32_t>::max());
  // Grow both arrays first so the push_backs cannot throw and leave them with different lengths.
  if (std::min(link_.capacity(), size_.capacity()) == n) Reserve(std::max<std::size_t>(8, 2 * n));
  const auto x = static_cast<std::uint32_t>(n);
  link_.push_back(x);
  size_.push_back(1);
  return x;
}

std::uint32_t DisjointSets::Find(std::uint32_t x) noexcept {
  assert(x < size());
  // Path halving: one pass, no stack; relinking to the grandparent keeps x in the same set and
  // only shortens paths, so the union-by-size height bound still holds.
  while (link_[x] != x) {
    link_[x] = link_[link_[x]];
    x = link_[x];
  }
  return x;
}

std::uint32_t DisjointSets::FindConst(std::uint32_t x) const noexcept {
  assert(x < size());
  while (link_[x] != x) x = link_[x];
  return x;
}

std::uint32_t DisjointSets::Union(std::uint32_t a, std::uint32_t b) noexcept {
  std::uint32_t ra = Find(a);
  std::uint32_t rb = Find(b);
  if (ra == rb) return ra;
  // Hang the smaller set under the larger: an element's depth then only grows when its set at
  // least doubles, so no path is longer than log2(set size).
  if (size_[ra] < size_[rb]) std::swap(ra, rb);
  link_[rb] = ra;
  size_[ra] += size_[rb];
  return ra;
}

std::size_t DisjointSets::ApproximateBytes() const noexcept {
  return sizeof(std::uint32_t) * (link_.capacity() + size_.capacity());
}

bool DisjointSets::CheckInvariants() const {
  const std::size_t n = size();
  if (size_.size() != n) return false;
  std::vector<std::uint32_t> members(n, 0);
  std::vector<std::uint32_t> height(n, 0);
  for (std::uint32_t x = 0; x < n; ++x) {
    std::uint32_t r = x;
    std::uint32_t steps = 0;
    while (link_[r] != r) {
      r = link_[r];
      // 32 steps would already need a set of 2^32 elements: this bounds the walk on a cycle.
      if (r >= n || ++steps > 32) return false;
    }
    ++members[r];
    height[r] = std::max(height[r], steps);
  }
  for (std::uint32_t r = 0; r < n; ++r) {
    if (link_[r] != r) continue;
    if (size_[r] != members[r]) return false;
    if ((std::uint64_t{1} << height[r]) > size_[r]) return false;  // union-by-size bound
  }
  return true;
}

}  // namespace semgraph::topology
