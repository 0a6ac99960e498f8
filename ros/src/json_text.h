// JSON text for the findings and summaries of semgraph::ros (private). Off the hot path.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace semgraph::ros::json {

/// A JSON string: quotes, backslash escapes, control characters as \u00XX; other bytes as given
/// (names are checked UTF-8 by the graph; a message quotes them).
inline std::string Quoted(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", u);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

/// Nanoseconds as exact decimal seconds ("12.5", "-0.000000001"): no rounding, so a stamp
/// printed here reads back to the same nanosecond.
inline std::string Seconds(std::int64_t ns) {
  const bool negative = ns < 0;
  const std::uint64_t magnitude =
      negative ? ~static_cast<std::uint64_t>(ns) + 1 : static_cast<std::uint64_t>(ns);
  std::string out = (negative ? "-" : "") + std::to_string(magnitude / 1'000'000'000u);
  std::uint64_t frac = magnitude % 1'000'000'000u;
  if (frac == 0) return out;
  char buf[16];
  std::snprintf(buf, sizeof buf, "%09llu", static_cast<unsigned long long>(frac));
  std::string digits = buf;
  while (digits.back() == '0') digits.pop_back();
  return out + "." + digits;
}

}  // namespace semgraph::ros::json
