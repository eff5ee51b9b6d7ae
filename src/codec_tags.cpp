// The subdivision tags section (format 3.4; format-spec/qsp_format.md, "Subdivision tags section"):
// OpenSubdiv tags in file order, the indices of crease, corner and hole in the output's numbering.
#include <algorithm>
#include <bit>
#include <cmath>
#include <string>
#include <vector>

#include "bytes.h"
#include "codec_sections.h"
#include "geometry_values.h"
#include "qsp/error.h"
#include "qsp/polymesh.h"

namespace qsp {
namespace {

constexpr const char* kSection = "subdivision tags section";

// A name or string is one word of the OBJ line: no space or control byte, not empty.
bool is_word(std::string_view s) {
  return !s.empty() &&
         std::none_of(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) <= 0x20; });
}

}  // namespace

std::string encode_tags_section(std::span<const SubdivisionTag> input, std::span<const std::uint32_t> vertex,
                                std::span<const std::uint32_t> face, bool keep_order) {
  // In the output's numbering, unless the order is kept (the order section numbers the output as the input).
  std::vector<SubdivisionTag> tags(input.begin(), input.end());
  for (std::size_t t = 0; t < tags.size() && !keep_order; ++t)
    if (tag_indices(tags[t].name) == TagIndices::kUnknown)
      throw Error(ErrorCode::kUsage,
                  "encode: tag " + std::to_string(t) + " ('" + tags[t].name +
                      "') indexes what qsp cannot renumber: keep the original order for it");
  if (!keep_order) {
    try {
      renumber_tags(tags, vertex, face);
    } catch (const Error& e) {
      throw Error(e.code(), std::string("encode: ") + e.what());
    }
  }
  std::string out;
  put_varint(out, tags.size());
  for (std::size_t t = 0; t < tags.size(); ++t) {
    const SubdivisionTag& tag = tags[t];
    const auto fail = [&](const std::string& what) {
      throw Error(ErrorCode::kUsage, "encode: tag " + std::to_string(t) + " ('" + tag.name + "') " + what);
    };
    if (!is_word(tag.name)) fail("has a name that is not one word");
    if (tag_indices(tag.name) == TagIndices::kEdges && tag.ints.size() % 2)
      fail("has an odd number of vertex indices");
    put_varint(out, tag.name.size());
    out += tag.name;
    put_varint(out, tag.ints.size());
    put_varint(out, tag.floats.size());
    put_varint(out, tag.strings.size());
    for (const std::int64_t i : tag.ints) put_varint(out, zigzag64(i));
    if (!tag.floats.empty()) {
      out += static_cast<char>(tag.float64 ? 8 : 4);
      for (const double x : tag.floats) {
        if (!std::isfinite(x)) fail("has a float that is not finite");
        if (tag.float64) {
          put_le(out, std::bit_cast<std::uint64_t>(x), 8);
        } else {
          const auto f = static_cast<float>(x);
          if (static_cast<double>(f) != x) fail("has a float binary32 does not hold (set float64)");
          put_le(out, std::bit_cast<std::uint32_t>(f), 4);
        }
      }
    }
    for (std::size_t s = 0; s < tag.strings.size(); ++s) {
      if (!is_word(tag.strings[s])) fail("has a string that is not one word");
      put_varint(out, tag.strings[s].size());
      out += tag.strings[s];
    }
  }
  return out;
}

std::vector<SubdivisionTag> decode_tags_section(std::string_view payload, std::uint64_t base_offset,
                                                std::uint64_t vertex_count, std::uint64_t face_count,
                                                bool order_section) {
  ByteReader in(payload, base_offset, kSection);
  // Each count is checked against the bytes left (every item costs at least one) before it allocates.
  const auto count = [&in](const char* what, bool at_least_one) {
    const std::uint64_t at = in.offset(), n = in.varint(what);
    if (n > in.left() || (at_least_one && n == 0))
      in.fail_at(std::string(what) + " " + std::to_string(n) + " is not " + (at_least_one ? "1" : "0") +
                     " to the " + std::to_string(in.left()) + " bytes left",
                 at);
    return n;
  };
  const auto word = [&in, &count](const char* what) {
    const std::uint64_t at = in.offset();
    const std::string_view s = in.take(count("length", true), what);
    if (!is_word(s)) in.fail_at(std::string(what) + " holds a space or control byte", at);
    return std::string(s);
  };
  std::vector<SubdivisionTag> tags(count("tag count", true));
  for (SubdivisionTag& tag : tags) {
    const std::uint64_t at = in.offset();
    tag.name = word("tag name");
    const TagIndices kind = tag_indices(tag.name);
    if (kind == TagIndices::kUnknown && !order_section)
      in.fail_at("tag '" + tag.name +
                     "' indexes what only the original order numbers, and the file has no order section",
                 at);
    const std::uint64_t ints = count("integer count", false), floats = count("float count", false),
                        strings = count("string count", false);
    if (kind == TagIndices::kEdges && ints % 2) in.fail_at("crease with an odd number of vertex indices", at);
    const std::uint64_t limit = kind == TagIndices::kFaces ? face_count : vertex_count;
    const bool indices =
        kind == TagIndices::kEdges || kind == TagIndices::kVertices || kind == TagIndices::kFaces;
    tag.ints.reserve(ints);
    for (std::uint64_t i = 0; i < ints; ++i) {
      const std::uint64_t where = in.offset();
      const std::int64_t v = unzigzag64(in.varint("integer"));
      if (indices && (v < 0 || static_cast<std::uint64_t>(v) >= limit))
        in.fail_at("tag '" + tag.name + "' names " + (kind == TagIndices::kFaces ? "face " : "vertex ") +
                       std::to_string(v) + " of " + std::to_string(limit),
                   where);
      tag.ints.push_back(v);
    }
    if (floats > 0) {
      const std::uint64_t where = in.offset();
      const std::uint8_t width = in.u8("float width");
      if (width != 4 && width != 8) in.fail_at("float width " + std::to_string(width) + " (4 or 8)", where);
      tag.float64 = width == 8;
      if (floats > in.left() / width)
        in.fail_at(
            std::to_string(floats) + " floats do not fit in the " + std::to_string(in.left()) + " bytes left",
            where);
      tag.floats.reserve(floats);
      for (std::uint64_t i = 0; i < floats; ++i) {
        const std::uint64_t f = in.offset();
        const double x =
            width == 8
                ? std::bit_cast<double>(in.le(8, "float"))
                : static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(in.le(4, "float"))));
        if (!std::isfinite(x)) in.fail_at("a float that is not finite", f);
        tag.floats.push_back(x);
      }
    }
    tag.strings.reserve(strings);
    for (std::uint64_t i = 0; i < strings; ++i) tag.strings.push_back(word("tag string"));
  }
  if (in.left() != 0) in.fail(std::to_string(in.left()) + " bytes after the last tag");
  return tags;
}

}  // namespace qsp
