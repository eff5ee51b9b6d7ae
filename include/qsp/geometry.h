// qsp/geometry.h: position coding along patch grids (used by the codec).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/partition.h"

namespace qsp {

// Which of its candidate headers an encode chose. It depends on the coordinates far more than on the
// stencils, so the codec lets one encode choose for the others of the same mesh.
struct GeometryChoice {
  bool repeats = false;  // coordinates may be coded as repeats of earlier values
  bool decimal = false;  // lossless: the decimal-grid plan, where there is one (else float bits)
};

// Sections above this many vertices run the range coder on a second thread by default: below it,
// starting a thread costs more than it saves.
inline constexpr std::uint32_t kCoderThreadAbove = 32768;

struct GeometryOptions {
  // 0 = lossless (float32 bit-exact). 1..30 = uniform grid over the bounding box's largest extent.
  std::uint32_t quantize_bits = 0;
  // The order the stencils are in (grid_layout's `order`); written to the file as a header flag.
  CodingOrder order = CodingOrder::kLayout;
  // nullopt: choose among the candidate headers (header_sample says how). Else code with this one only
  // (normal chaining and revision 6 are still tried where the options below allow).
  std::optional<GeometryChoice> choice = std::nullopt;
  // 0: every candidate header is coded in full and the smallest section kept. N > 0: the header (and
  // chaining) is chosen on the first N vertices' encodes, scaled to the section, which is then coded
  // once; a section of at most N vertices is tried in full.
  std::uint32_t header_sample = 0;
  // Whether normal chaining (revision 5) is tried where the chosen header's statistics say it may pay.
  bool try_chaining = true;
  // With a header sample: value repeats only where the estimate saves at least 1/32 of the section.
  // Decoding repeats costs a quarter of the geometry decode (mh_base), for about 1% on meshes where
  // values repeat by chance; on CAD-like meshes they save a third.
  bool repeats_must_pay = false;
  // Whether a second thread runs the range coder while the coding loop predicts: nullopt = for sections
  // of more than kCoderThreadAbove vertices. The bytes are the same either way (tests force both).
  std::optional<bool> coder_thread = std::nullopt;
  // Geometry revision 6 (shape transfers, magnitude classes, logistic mixing; format 2.2): nullopt =
  // tried and kept where smaller when the headers are tried in full, not with a sample; true = always;
  // false = never (the section then decodes with format 2.1 readers).
  std::optional<bool> shapes = std::nullopt;
};

// Encodes positions (3 floats per vertex, in coding order) using, for each vertex, the grid stencil of
// already-coded neighbours. Lossless mode is bit-exact for every float, NaN payloads and -0 included;
// it detects decimal-grid data (e.g. every coordinate written with 4 decimals) and codes its integers.
// Returns self-delimiting bytes (see format-spec/qsp_format.md, "Geometry section"); if `chosen` is
// given, it gets the header choice the section was coded with.
std::string encode_geometry(std::span<const float> positions, std::span<const GridLayout::Stencil> stencil,
                            const GeometryOptions& options, GeometryChoice* chosen = nullptr);

// Inverse of encode_geometry for `vertex_count` vertices and the same stencils. Throws Error(kFormat)
// on any inconsistency; never reads outside `bytes`. Safe on untrusted input.
std::vector<float> decode_geometry(std::string_view bytes, std::span<const GridLayout::Stencil> stencil,
                                   std::uint32_t vertex_count);

// The coding order a geometry section was written in (its revision byte; in revisions 4-6 a flag of its
// third byte), so the caller can build the matching stencils. Throws Error(kFormat) if the section is
// too short or of an unknown revision.
CodingOrder geometry_coding_order(std::string_view bytes);

// Largest absolute coordinate error a quantized encoding introduced: 0 when bit-identical, +inf if a
// NaN or infinity differs. Throws Error(kInternal) if the sizes differ.
double max_geometry_error(std::span<const float> original, std::span<const float> decoded);

// The float a decimal-grid integer stands for: the binary32 nearest to n / 10^k, ties to even (what
// std::from_chars gives for the decimal text). |n| < 2^40, 0 <= k <= 9. Exposed for tests and tools.
float decimal_grid_value(std::int64_t n, int k);

}  // namespace qsp
