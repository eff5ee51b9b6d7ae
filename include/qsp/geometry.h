// qsp/geometry.h: what a .qsp's geometry section can say about how its positions were coded
// (format-spec/geometry_section.md): the coding order and the optional tools. The coder itself is
// internal to the library (src/geometry_coder.h).
#pragma once

#include <cstdint>
#include <string>

namespace qsp {

// Coding orders of the geometry. kLayout: the layout numbering (schematic vertices, edges, patch
// interiors), with predictors across patches. kPatch: patch by patch, row by row, each vertex where its
// first patch reaches it, with its neighbours across patch sides.
enum class CodingOrder : std::uint8_t { kLayout = 0, kPatch = 1 };

// The optional tools of a geometry section: the bits of its first byte (geometry_section.md, "Header").
// Every combination is valid; an encoder chooses them per mesh.
namespace geometry_tool {
inline constexpr std::uint8_t kValueRepeats = 0x01;    // coordinates coded as repeats of earlier values
inline constexpr std::uint8_t kLayoutOrder = 0x02;     // CodingOrder::kLayout (clear: kPatch)
inline constexpr std::uint8_t kNormalChaining = 0x04;  // axes y, z predicted along the normal as well
inline constexpr std::uint8_t kCellShapes = 0x08;      // shrunk parallelogram and shape transfers
inline constexpr std::uint8_t kLogisticMixing = 0x10;  // magnitude classes, length prior, 4-model mixing
inline constexpr std::uint8_t kMirror = 0x20;  // vertices with a mirror source predicted from it (3.17)
inline constexpr std::uint8_t kAll = 0x3F;     // the other bits are reserved
}  // namespace geometry_tool

// The tools in `tools` other than the coding order, as words for people ("value repeats, normal
// chaining"; "none"). Reserved bits are ignored. Never throws but std::bad_alloc.
std::string geometry_tool_names(std::uint8_t tools);

}  // namespace qsp
