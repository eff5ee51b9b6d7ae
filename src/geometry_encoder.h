// The geometry encoder: one section with a given header (geometry_encoder.cpp). Which header and tools
// a section gets is the search's (geometry_search.cpp).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "geometry_chain.h"
#include "geometry_header.h"
#include "geometry_hood.h"

namespace qsp {

// The section for the first `count` vertices of `positions` (3 floats a vertex, coding order) with
// header `h` (a prefix codes on its own: stencils only look back). `coder_thread`: as
// GeometryOptions::coder_thread. With `cue`, the chaining model runs even without the tool and counts
// where it would have paid.
std::string encode_with(std::span<const float> positions, const Hoods& hoods, std::uint32_t count,
                        const Header& h, std::optional<bool> coder_thread, ChainCue* cue = nullptr);

}  // namespace qsp
