// Counts in messages and reports: "1 vertex", "3 vertices"; and comma-separated lists of them.
#pragma once

#include <cstdint>
#include <string>

namespace qsp::detail {

inline std::string plural(std::uint64_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// Appends ", 3 normals" (no comma first) unless n is 0.
inline void append_count(std::string& out, std::uint64_t n, const char* one, const char* many) {
  if (n == 0) return;
  if (!out.empty()) out += ", ";
  out += plural(n, one, many);
}

}  // namespace qsp::detail
