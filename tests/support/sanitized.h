// File: tests/support/sanitized.h
//
// kSanitized: whether this test is built with AddressSanitizer (CI's ASan + UBSan stage).
// Monte Carlo tests draw fewer samples there (Draws): under a sanitizer they check the code
// paths for memory errors and undefined behaviour, which a few thousand draws exercise as well
// as twenty thousand; the statistics are checked by the plain build's full draw count. Their
// tolerances are in standard errors of the count actually drawn, so they hold for both.
#pragma once

namespace semgraph::testing {

#if defined(__SANITIZE_ADDRESS__)  // g++
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)  // clang
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

/// n, or n / 5 under a sanitizer.
constexpr int Draws(int n) { return kSanitized ? n / 5 : n; }

}  // namespace semgraph::testing
