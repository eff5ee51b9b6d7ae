// src/non_quads.h (internal): the one report of faces that are not quads, for the OBJ, OFF and PLY
// readers in quads mode.
#pragma once

#include <cstdint>
#include <string>

#include "plural.h"
#include "qsp/error.h"

namespace qsp::detail {

// A face's corner count in words: "triangle", "no vertices", "1 vertex", "5 vertices".
inline std::string corners_name(std::uint64_t n) {
  if (n == 3) return "triangle";
  if (n == 0) return "no vertices";
  return plural(n, "vertex", "vertices");
}

// Faces that are not quads: counted all the way through so the message can say how many, the first
// three kept as examples, each at a place (its line, or its face index where the file has no lines).
struct NonQuads {
  std::uint64_t count = 0;
  std::uint64_t at[3] = {}, corners[3] = {};  // the first ones

  void add(std::uint64_t place, std::uint64_t n) {
    if (count < 3) {
      at[count] = place;
      corners[count] = n;
    }
    ++count;
  }
  // Adds those of the text after this one's, which starts `line_offset` lines further on.
  void merge(const NonQuads& later, std::uint64_t line_offset) {
    std::uint64_t i = 0;
    for (; i < later.count && i < 3 && count < 3; ++i) add(later.at[i] + line_offset, later.corners[i]);
    count += later.count - i;
  }
  // Throws Error(kNotQuad) if there were any: WHERE, then "2 faces are not quads (first: line 10: triangle,
  // line 12: 5 vertices); ...", each example's place after `unit` ("line" or "face").
  void throw_if_any(const std::string& where, const char* unit) const {
    if (count == 0) return;
    std::string examples;
    for (std::uint64_t i = 0; i < count && i < 3; ++i) {
      if (i > 0) examples += ", ";
      examples += std::string(unit) + " " + std::to_string(at[i]) + ": " + corners_name(corners[i]);
    }
    std::string msg = where;
    if (count == 1) {
      msg += "1 face is not a quad (" + examples + ")";
    } else {
      msg += std::to_string(count) + " faces are not quads (first: " + examples + (count > 3 ? ", ..." : "") +
             ")";
    }
    msg += "; qsp stores quad meshes only and never triangulates or drops faces";
    throw Error(ErrorCode::kNotQuad, msg);
  }
  // The same for a text file, its examples at lines: "SOURCE:LINE: ..." with the first one's line.
  void throw_if_any(std::string_view source) const {
    if (count) throw_if_any(std::string(source) + ":" + std::to_string(at[0]) + ": ", "line");
  }
};

}  // namespace qsp::detail
