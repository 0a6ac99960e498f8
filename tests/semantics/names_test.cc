#include "semgraph/semantics/names.h"

#include <gtest/gtest.h>

namespace semgraph::semantics {
namespace {
TEST(NameTable, InternsOnce) {
  NameTable names;
  auto a = names.Intern("a");
  ASSERT_TRUE(a);
  EXPECT_EQ(*names.Intern("a"), *a);
  EXPECT_EQ(names.name(*a), "a");
}
}  // namespace
}  // namespace semgraph::semantics
