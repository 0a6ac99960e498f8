// File: semgraph/base/expected.h
//
// Expected<T, E>: a value or an error, the return type of every fallible semgraph call
// (std::expected is C++23; Debian has no tl-expected). Deliberately small: no monadic
// chaining, no exceptions. Accessing the wrong alternative is a programming error and aborts
// via SEMGRAPH_DEMAND.
//
// Invariants: holds exactly one of T or E. (Copy/move/destroy are user-provided even for
// trivial T and E: clang 14 does not implement conditionally trivial special members.)
// Cost: construction and access are O(1), noexcept, allocation-free (beyond what T or E do).
#pragma once

#include <new>
#include <type_traits>
#include <utility>

#include "semgraph/base/demand.h"

namespace semgraph::base {

/// Wraps an error so that `return Unexpected{err};` converts to any Expected<T, E>.
template <class E>
struct Unexpected {
  E error;
};
template <class E>
Unexpected(E) -> Unexpected<E>;

template <class T, class E>
class [[nodiscard]] Expected {
 public:
  using value_type = T;
  using error_type = E;

  // NOLINTNEXTLINE(google-explicit-constructor): implicit like std::expected.
  Expected(const T& value) noexcept(std::is_nothrow_copy_constructible_v<T>) : ok_(true) {
    ::new (&storage_.value) T(value);
  }
  // NOLINTNEXTLINE(google-explicit-constructor)
  Expected(T&& value) noexcept(std::is_nothrow_move_constructible_v<T>) : ok_(true) {
    ::new (&storage_.value) T(std::move(value));
  }
  template <class G>
  // NOLINTNEXTLINE(google-explicit-constructor)
  Expected(Unexpected<G> unexpected) noexcept(std::is_nothrow_constructible_v<E, G&&>)
      : ok_(false) {
    ::new (&storage_.error) E(std::move(unexpected.error));
  }

  Expected(const Expected& other) : ok_(other.ok_) {
    if (ok_)
      ::new (&storage_.value) T(other.storage_.value);
    else
      ::new (&storage_.error) E(other.storage_.error);
  }
  Expected(Expected&& other) noexcept(
      std::is_nothrow_move_constructible_v<T>&& std::is_nothrow_move_constructible_v<E>)
      : ok_(other.ok_) {
    if (ok_)
      ::new (&storage_.value) T(std::move(other.storage_.value));
    else
      ::new (&storage_.error) E(std::move(other.storage_.error));
  }
  Expected& operator=(const Expected& other) {
    if (this != &other) {
      Destroy();
      ::new (this) Expected(other);
    }
    return *this;
  }
  Expected& operator=(Expected&& other) noexcept {
    if (this != &other) {
      Destroy();
      ::new (this) Expected(std::move(other));
    }
    return *this;
  }
  ~Expected() { Destroy(); }

  [[nodiscard]] bool has_value() const noexcept { return ok_; }
  explicit operator bool() const noexcept { return ok_; }

  [[nodiscard]] const T& value() const& noexcept {
    SEMGRAPH_DEMAND(ok_);
    return storage_.value;
  }
  [[nodiscard]] T& value() & noexcept {
    SEMGRAPH_DEMAND(ok_);
    return storage_.value;
  }
  [[nodiscard]] T&& value() && noexcept {
    SEMGRAPH_DEMAND(ok_);
    return std::move(storage_.value);
  }
  [[nodiscard]] const E& error() const& noexcept {
    SEMGRAPH_DEMAND(!ok_);
    return storage_.error;
  }
  [[nodiscard]] E& error() & noexcept {
    SEMGRAPH_DEMAND(!ok_);
    return storage_.error;
  }
  [[nodiscard]] E&& error() && noexcept {
    SEMGRAPH_DEMAND(!ok_);
    return std::move(storage_.error);
  }
  const T& operator*() const& noexcept { return value(); }
  T& operator*() & noexcept { return value(); }
  T&& operator*() && noexcept { return std::move(*this).value(); }
  const T* operator->() const noexcept { return &value(); }
  T* operator->() noexcept { return &value(); }

 private:
  void Destroy() noexcept {
    if (ok_)
      storage_.value.~T();
    else
      storage_.error.~E();
  }
  union Storage {
    Storage() noexcept {}
    ~Storage() {}
    T value;
    E error;
  } storage_;
  bool ok_;
};

/// Expected<void, E>: success carries nothing.
struct Ok {};

}  // namespace semgraph::base
