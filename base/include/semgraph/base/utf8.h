// File: semgraph/base/utf8.h
//
// The one UTF-8 decoder of semgraph: name validation (semantics/names.cc), the script reader's
// encoding check (tools yaml_tree.cc) and the JSON-lines writer (tools script_runner.cc) all
// decode through it, so that they agree on what well-formed UTF-8 is.
//
// Well-formed (Unicode 15, Table 3-7): a sequence of 1 to 4 bytes in shortest form, encoding a
// code point of at most U+10FFFF that is not a surrogate (U+D800..U+DFFF). Rejected: a stray
// continuation byte, a lead byte 0xC0, 0xC1 or 0xF5..0xFF, a sequence cut short by the end of
// the text or by a byte that is not a continuation, an overlong form, a surrogate, a code point
// above U+10FFFF.
// Cost: O(1) per sequence, constexpr, noexcept, no allocation.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace semgraph::base {

/// A decoded sequence: its length in bytes (1-4; 0 when the bytes at the position are not a
/// well-formed sequence) and its code point (meaningful only when length > 0).
struct Utf8Sequence {
  std::size_t length = 0;
  std::uint32_t code_point = 0;
};

/// Decodes the sequence starting at text[i] (i < text.size()).
[[nodiscard]] constexpr Utf8Sequence DecodeUtf8(std::string_view text, std::size_t i) noexcept {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b0 = byte(i);
  if (b0 < 0x80) return {1, b0};
  std::size_t length;
  std::uint32_t code, min_code;  // below min_code the sequence is overlong
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    length = 2, code = b0 & 0x1Fu, min_code = 0x80;
  } else if (b0 >= 0xE0 && b0 <= 0xEF) {
    length = 3, code = b0 & 0x0Fu, min_code = 0x800;
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    length = 4, code = b0 & 0x07u, min_code = 0x10000;
  } else {
    return {};
  }
  if (length > text.size() - i) return {};
  for (std::size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0u) != 0x80u) return {};
    code = (code << 6) | (byte(i + k) & 0x3Fu);
  }
  if (code < min_code || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return {};
  return {length, code};
}

/// The length of the well-formed sequence at text[i] (1-4), or 0.
[[nodiscard]] constexpr std::size_t Utf8Length(std::string_view text, std::size_t i) noexcept {
  return DecodeUtf8(text, i).length;
}

}  // namespace semgraph::base
