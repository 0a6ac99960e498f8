// Private to core/src: the name-table guard of the build operations (add.cc, joints.cc).
#pragma once

#include <cstddef>

#include "semgraph/semantics/names.h"

namespace semgraph::core::internal {

// Restores the name table on every early return of a build operation (atomicity): names the
// operation interned are dropped unless it reaches Commit(), after its last possible failure.
class NameRollback {
 public:
  explicit NameRollback(semantics::NameTable& names) : names_(names), size_(names.size()) {}
  NameRollback(const NameRollback&) = delete;
  NameRollback& operator=(const NameRollback&) = delete;
  ~NameRollback() {
    if (armed_) names_.TruncateTo(size_);
  }
  void Commit() noexcept { armed_ = false; }

 private:
  semantics::NameTable& names_;
  std::size_t size_;
  bool armed_ = true;
};

}  // namespace semgraph::core::internal
