// src/match_levels.h (internal): what match.cpp's quad matching shares with the polygon matching of
// match_polygons.cpp: the level at which two prepared quad meshes' canonical forms differ, and the
// nearest pairing of interchangeable points (unreferenced vertices).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "qsp/match.h"

namespace qsp::detail {

// kNone when pa's and pb's canonical forms (codes in canonical order, unreferenced vertex counts) are
// equal; else the first level that differs (component count, sizes, extraordinary vertices,
// schematic, code, unreferenced) and `why` (without the level's name; "A has ..., B has ...").
MatchLevel quad_difference(const MatchInput& pa, const MatchInput& pb, std::string& why);

// Pairs xs[i] with ys[to[i]] at minimum total squared distance (match()'s method for unreferenced
// vertices and interchangeable components; exact up to 256 points). Sets `ambiguous` when another
// pairing is as near and `exhaustive` to false when the pairing is not proven nearest.
std::vector<std::uint32_t> pair_nearest(const std::vector<std::array<double, 3>>& xs,
                                        const std::vector<std::array<double, 3>>& ys, double tie_tolerance,
                                        bool& ambiguous, bool& exhaustive);

}  // namespace qsp::detail
