// The geometry coder (format-spec/geometry_section.md): positions <-> the geometry section, along the
// stencils of a coding order (stencil.h). Internal: the codec calls it, tests and tools reach it through
// the private include path. Its parts, each in its own file:
//   geometry_values.h   value domains: quantized grid, decimal grids, float images
//   geometry_hood.h     neighbourhoods: kinds, context kinds, derived neighbours
//   geometry_predict.h  candidates, shape transfers, the blend, fixed and float predictors
//   geometry_chain.h    normal chaining
//   geometry_model.h    the residual model and its mixed and logistic decisions
//   geometry_repeats.h  value repeats
//   geometry_header.h   the header: tools, bits, axis descriptors
//   geometry_loop.h     the coding loop encoder and decoder share
//   geometry_sink.h     the encoder's symbols and the coder thread
//   geometry_encoder.cpp, geometry_decoder.cpp, geometry_search.cpp (the encoder's choice of header
//   and tools)
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/geometry.h"
#include "stencil.h"

namespace qsp {

// Which of its candidate headers an encode chose. It depends on the coordinates far more than on the
// stencils, so the codec lets one encode choose for the others of the same mesh.
struct GeometryChoice {
  bool repeats = false;  // coordinates may be coded as repeats of earlier values
  bool decimal = false;  // lossless: the decimal-grid plan, where there is one (else float bits)
  bool mirror = false;   // vertices predicted from their stencils' mirror sources
};

// Sections above this many vertices run the range coder on a second thread by default: below it,
// starting a thread costs more than it saves.
inline constexpr std::uint32_t kCoderThreadAbove = 32768;

// GeometryOptions::repeats_must_pay's bar: value repeats must save 1/kRepeatsMustSave of the section.
inline constexpr int kRepeatsMustSave = 32;

struct GeometryOptions {
  // 0 = lossless (float32 bit-exact). 1..30 = uniform grid over the bounding box's largest extent.
  std::uint32_t quantize_bits = 0;
  // The order the stencils are in (stencil.h); written to the file as the layout-order tool bit.
  CodingOrder order = CodingOrder::kLayout;
  // nullopt: choose among the candidate headers (header_sample says how). Else code with this one only
  // (normal chaining and the costly tools are still tried where the options below allow).
  std::optional<GeometryChoice> choice = std::nullopt;
  // 0: every candidate header is coded in full and the smallest section kept. N > 0: the header (and
  // chaining) is chosen on the first N vertices' encodes, scaled to the section, which is then coded
  // once; a section of at most N vertices is tried in full.
  std::uint32_t header_sample = 0;
  // Whether normal chaining is tried where the chosen header's statistics say it may pay.
  bool try_chaining = true;
  // With a header sample: value repeats only where the estimate saves at least 1/kRepeatsMustSave of
  // the section. Decoding repeats costs a quarter of the geometry decode (mh_base), for about 1% on
  // meshes where values repeat by chance; on CAD-like meshes they save a third.
  bool repeats_must_pay = false;
  // Whether a second thread runs the range coder while the coding loop predicts: nullopt = for sections
  // of more than kCoderThreadAbove vertices. The bytes are the same either way (tests force both).
  std::optional<bool> coder_thread = std::nullopt;
  // Whether the cell shapes and logistic mixing tools are tried together, and kept where smaller, when
  // the headers are tried in full: a few percent smaller, twice the decoder's work.
  bool try_costly_tools = false;
  // Whether the headers are also tried with mirror prediction, where the stencils name mirror sources
  // and every axis is an integer axis.
  bool try_mirror = false;
  // What mirror prediction costs besides the section (the symmetry section's bytes), added to its
  // headers' sizes when they are compared.
  std::uint32_t mirror_bytes = 0;
  // Tests and goldens: code with exactly these tools (geometry_tool bits; the layout-order bit is
  // ignored, `order` names the order) and no trials, choosing only among the value plans.
  std::optional<std::uint8_t> tools = std::nullopt;
};

// Encodes positions (3 floats per vertex, in coding order) using, for each vertex, the stencil of
// already-coded neighbours. Lossless mode is bit-exact for every float, NaN payloads and -0 included;
// it detects decimal-grid data (e.g. every coordinate written with 4 decimals) and codes its integers.
// Returns the section's payload; if `chosen` is given, it gets the header choice the section was coded
// with. Throws Error(kUsage) for a partial positions array or quantize_bits > 30, kLimit for more than
// kMaxVertices, kBadNumber for a NaN or infinity to quantize, kInternal for stencils that are not
// one per vertex or refer forward.
std::string encode_geometry(std::span<const float> positions, std::span<const Stencil> stencil,
                            const GeometryOptions& options, GeometryChoice* chosen = nullptr);

// Inverse of encode_geometry for `vertex_count` vertices and the same stencils; `base_offset` is the
// section's payload offset in the file, for messages. Throws Error(kFormat) "geometry section: ...
// (at byte offset N)" on any inconsistency; never reads outside `bytes`. Safe on untrusted input.
std::vector<float> decode_geometry(std::string_view bytes, std::uint64_t base_offset,
                                   std::span<const Stencil> stencil, std::uint32_t vertex_count);

// The tools byte of a geometry section (its first byte), checked: Error(kFormat) if the section is
// empty or a reserved bit is set.
std::uint8_t geometry_tools(std::string_view bytes, std::uint64_t base_offset);

// The quantization bits of a geometry section (its second byte: 0 lossless, 1..30), checked as
// geometry_tools() checks the first.
std::uint8_t geometry_quantize_bits(std::string_view bytes, std::uint64_t base_offset);

// The coding order a tools byte names.
inline CodingOrder coding_order(std::uint8_t tools) {
  return (tools & geometry_tool::kLayoutOrder) ? CodingOrder::kLayout : CodingOrder::kPatch;
}

// Largest absolute coordinate error a quantized encoding introduced: 0 when bit-identical, +inf if a
// NaN or infinity differs. Throws Error(kUsage) if the sizes differ.
double max_geometry_error(std::span<const float> original, std::span<const float> decoded);

}  // namespace qsp
