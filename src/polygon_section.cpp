// The polygons section (format-spec/qsp_format.md, "Polygons section", format 3.1): the region codes
// and glue of qsp/regions.h entropy-coded in the order rebuild_polygons' traversal asks for them; in files
// before 3.12, then the interior vertices' positions as a geometry payload of their own (from 3.12 the
// geometry section codes them: interior_stencils.cpp).
#include <algorithm>
#include <string>
#include <type_traits>
#include <vector>

#include "bytes.h"
#include "codec_sections.h"
#include "entropy.h"
#include "geometry_coder.h"
#include "qsp/error.h"
#include "region_source.h"
#include "stencil.h"

namespace qsp {
namespace {

using detail::RegionSource;
using detail::RegionValue;
using detail::StartCode;

[[noreturn]] void internal(const std::string& what) {
  throw Error(ErrorCode::kInternal, "polygons section: " + what);
}

// The same code writes and reads every symbol: IO either codes the value it is given and returns it
// (EncodeIO) or ignores it and returns the value decoded (DecodeIO).
struct EncodeIO {
  RangeEncoder* enc;
  unsigned bit(BitModel& m, unsigned b) {
    enc->encode_bit(m, b);
    return b;
  }
  std::uint64_t integer(IntModel& m, std::uint64_t v) {
    if (v > 0xFFFFFFFEu) internal("a value past 2^32 - 2");
    m.encode(*enc, static_cast<std::uint32_t>(v));
    return v;
  }
};
struct DecodeIO {
  RangeDecoder* dec;
  unsigned bit(BitModel& m, unsigned) { return dec->decode_bit(m); }
  std::uint64_t integer(IntModel& m, std::uint64_t) { return m.decode(*dec); }
};

// The section's models and contexts (the spec's "Polygons section" names them).
template <class IO>
class SymbolCoder {
 public:
  explicit SymbolCoder(IO io) : io_(io) {}
  // The encoder checks what it is given (the codes are canonical_regions'); the decoder's values are
  // checked by the traversal.
  static constexpr bool kEncoding = std::is_same_v<IO, EncodeIO>;

  StartCode start(const StartCode& s) {
    prev_class_ = 0;
    if (io_.bit(start_free_, s.start == RegionStart::kFree)) return {RegionStart::kFree, 0, 0};
    if (kEncoding && (s.loop < loop_ || (s.loop == loop_ && s.position < position_)))
      internal("starts out of order");
    const std::uint64_t dl = io_.integer(start_loop_, s.loop - loop_);
    position_ = dl == 0 ? position_ + io_.integer(start_step_, s.position - position_)
                        : io_.integer(start_position_, s.position);
    loop_ += dl;
    return {RegionStart::kEdge, loop_, position_};
  }
  std::uint64_t degree(std::uint64_t d) {
    const unsigned ctx = prev_class_;
    std::uint64_t out = 3;
    if (!io_.bit(triangle_[ctx], d == 3)) {
      if (kEncoding && d < 5) internal("a degree of 4 or below 3");
      out = 5 + io_.integer(big_[ctx], d - 5);
    }
    prev_class_ = out == 3 ? 1 : 2;
    prev_symbol_ = 5;
    return out;
  }
  std::uint64_t corner(bool last, std::uint64_t s) {
    if (s > 4) internal("an unknown corner symbol");
    BitModel* m = corner_[(last ? 6 : 0) + prev_symbol_];
    std::uint64_t out = 0;
    if (!io_.bit(m[0], s == 0)) {
      out = 1;
      if (!io_.bit(m[1], s == 1)) {
        out = 2;
        if (!io_.bit(m[2], s == 2)) out = 3 + io_.bit(m[3], s == 4);
      }
    }
    prev_symbol_ = static_cast<unsigned>(out);
    return out;
  }
  std::uint64_t value(RegionValue kind, std::uint64_t x) {
    switch (kind) {
      case RegionValue::kHoleLoop:
        return io_.bit(same_loop_, x == 0) ? 0 : 1 + io_.integer(hole_loop_, x - 1);
      case RegionValue::kHoleStep:
        return io_.integer(hole_step_, x);
      case RegionValue::kHolePosition:
        return io_.integer(hole_position_, x);
      case RegionValue::kInteriorBack:
        return io_.integer(interior_back_, x);
    }
    internal("an unknown value kind");
  }
  std::uint64_t open(std::uint32_t edge, std::uint32_t degree, std::uint64_t x) {
    if (x > 1) internal("an edge flag other than 0 or 1");
    return io_.bit(open_[std::min<std::uint32_t>(edge, 2) + (degree == 3 ? 3 : 0)], static_cast<unsigned>(x));
  }
  // Glue group sizes, first refs and members: sizes minus 2, gaps minus 1 (the first group's first ref
  // as it is).
  std::uint64_t glue_size(std::uint64_t n) { return 2 + io_.integer(glue_size_, n - 2); }
  std::uint64_t glue_first(bool first, std::uint64_t prev, std::uint64_t x) {
    return first ? io_.integer(glue_gap_, x) : prev + 1 + io_.integer(glue_gap_, x - prev - 1);
  }
  std::uint64_t glue_member(std::uint64_t prev, std::uint64_t x) {
    return prev + 1 + io_.integer(glue_step_, x - prev - 1);
  }

 private:
  IO io_;
  unsigned prev_class_ = 0;   // the previous face's degree in the region: 0 none, 1 triangle, 2 more
  unsigned prev_symbol_ = 5;  // the previous corner's symbol in the face, 5 at its first coded corner
  std::uint64_t loop_ = 0, position_ = 0;  // the previous edge start
  BitModel start_free_, same_loop_;
  BitModel triangle_[3];
  BitModel corner_[12][4];
  BitModel open_[6];
  IntModel start_loop_, start_step_, start_position_, big_[3], hole_loop_, hole_step_, hole_position_,
      interior_back_, glue_size_, glue_gap_, glue_step_;
};

// canonical_regions' codes as rebuild_from reads them, each symbol coded as it is read.
class RecordingSource final : public RegionSource {
 public:
  RecordingSource(const RegionCodes& codes, RangeEncoder& enc) : inner_(codes), coder_(EncodeIO{&enc}) {}
  StartCode start() override { return coder_.start(inner_.start()); }
  std::uint64_t degree() override { return coder_.degree(some(inner_.degree())); }
  std::uint64_t corner(bool last) override { return coder_.corner(last, some(inner_.corner(last))); }
  std::uint64_t value(RegionValue kind) override { return coder_.value(kind, some(inner_.value(kind))); }
  std::uint64_t open(std::uint32_t edge, std::uint32_t degree) override {
    return coder_.open(edge, degree, some(inner_.open(edge, degree)));
  }
  bool region_done() override { return inner_.region_done(); }
  SymbolCoder<EncodeIO>& coder() { return coder_; }

 private:
  static std::uint64_t some(std::uint64_t x) {
    if (x == kEnd) internal("the region codes end early");
    return x;
  }
  detail::CodesSource inner_;
  SymbolCoder<EncodeIO> coder_;
};

// The section's stream as rebuild_from reads it.
class StreamSource final : public RegionSource {
 public:
  explicit StreamSource(RangeDecoder& dec) : coder_(DecodeIO{&dec}) {}
  StartCode start() override { return coder_.start({}); }
  std::uint64_t degree() override { return coder_.degree(0); }
  std::uint64_t corner(bool last) override { return coder_.corner(last, 0); }
  std::uint64_t value(RegionValue kind) override { return coder_.value(kind, 0); }
  std::uint64_t open(std::uint32_t edge, std::uint32_t degree) override {
    return coder_.open(edge, degree, 0);
  }
  bool region_done() override { return true; }
  SymbolCoder<DecodeIO>& coder() { return coder_; }

 private:
  SymbolCoder<DecodeIO> coder_;
};

// Interior positions: each predicted from the one before it (a chain; the stencil's w).
std::vector<Stencil> chain_stencils(std::uint32_t n) {
  std::vector<Stencil> s(n);
  for (std::uint32_t k = 1; k < n; ++k) s[k].w = k - 1;
  return s;
}

[[noreturn]] void fail(const std::string& what, std::uint64_t at) {
  throw Error(ErrorCode::kFormat,
              "polygons section: " + what + " (at byte offset " + std::to_string(at) + ")");
}

// Every symbol costs at least one binary decision, and none costs less than ~0.00156 bits (codec.cpp's
// bound for the geometry section): a stream of B bytes holds fewer than this many per byte.
constexpr std::uint64_t kMaxSymbolsPerByte = 2048;

}  // namespace

std::string encode_polygons_section(std::span<const std::uint32_t> layout_quads,
                                    const Adjacency& layout_adjacency, const RegionCodes& codes,
                                    PolygonFaces* rebuilt) {
  std::string stream;
  RangeEncoder enc(stream);
  RecordingSource source(codes, enc);
  const std::size_t groups = codes.glue_offsets.size() - 1;
  for (std::size_t g = 0; g < groups; ++g) {
    const std::uint32_t b = codes.glue_offsets[g], e = codes.glue_offsets[g + 1];
    source.coder().glue_size(e - b);
    source.coder().glue_first(g == 0, g == 0 ? 0 : codes.glue[codes.glue_offsets[g - 1]], codes.glue[b]);
    for (std::uint32_t i = b + 1; i < e; ++i) source.coder().glue_member(codes.glue[i - 1], codes.glue[i]);
  }
  PolygonFaces faces =
      detail::rebuild_from(layout_quads, layout_adjacency, codes.layout_vertices, codes.interior_vertices,
                           codes.regions.size(), codes.glue_offsets, codes.glue, source, kPolygonSizeLimit);
  enc.finish();
  std::string out;
  put_varint(out, codes.interior_vertices);
  put_varint(out, codes.regions.size());
  put_varint(out, groups);
  put_varint(out, stream.size());
  out += stream;
  if (rebuilt) *rebuilt = std::move(faces);
  return out;
}

PolygonStream decode_polygon_stream(std::string_view payload, std::uint64_t base_offset,
                                    std::span<const std::uint32_t> layout_quads,
                                    const Adjacency& layout_adjacency, const DecodeLimits& limits) {
  ByteReader r(payload, base_offset, "polygons section");
  const std::uint64_t vq = layout_adjacency.vertex_count;
  std::uint64_t at = r.offset();
  const std::uint64_t interior = r.varint("interior vertex count");
  if (vq + interior >= kPolygonSizeLimit) fail("more vertices than the format's 2^31 - 1", at);
  if (vq + interior > limits.max_vertices)
    throw Error(ErrorCode::kLimit, "polygons section: " + std::to_string(vq + interior) +
                                       " vertices (with the interior ones) exceed the limit " +
                                       std::to_string(limits.max_vertices) + " (at byte offset " +
                                       std::to_string(at) + ")");
  const std::uint64_t regions_at = r.offset();
  const std::uint64_t regions = r.varint("region count");
  const std::uint64_t glue_at = r.offset();
  const std::uint64_t groups = r.varint("glue group count");
  const std::uint64_t stream_at = r.offset();
  const std::uint64_t length = r.varint("stream length");
  if (length > r.left()) fail("the stream runs past the section", stream_at);
  const std::uint64_t most = kMaxSymbolsPerByte * (length + 8);
  if (interior > most) fail("more interior vertices than the stream can hold", at);
  if (regions > most) fail("more regions than the stream can hold", regions_at);
  if (groups > most || 2 * groups > vq + interior) fail("more glue groups than the vertices allow", glue_at);
  const std::uint64_t stream_offset = r.offset();
  const std::string_view stream = payload.substr(r.pos(), length);
  const auto refs = static_cast<std::uint32_t>(vq + interior);

  RangeDecoder dec(stream, stream_offset, "polygons section");
  StreamSource source(dec);
  std::vector<std::uint32_t> glue_offsets{0}, glue;
  std::uint64_t prev_first = 0;
  for (std::uint64_t g = 0; g < groups; ++g) {
    const std::uint64_t n = source.coder().glue_size(0);
    std::uint64_t x = source.coder().glue_first(g == 0, prev_first, 0);
    if (n > refs || x >= refs)
      fail("glue group " + std::to_string(g) + " names a vertex out of range", dec.offset());
    prev_first = x;
    glue.push_back(static_cast<std::uint32_t>(x));
    for (std::uint64_t i = 1; i < n; ++i) {
      x = source.coder().glue_member(x, 0);
      if (x >= refs) fail("glue group " + std::to_string(g) + " names a vertex out of range", dec.offset());
      glue.push_back(static_cast<std::uint32_t>(x));
    }
    glue_offsets.push_back(static_cast<std::uint32_t>(glue.size()));
  }
  PolygonStream out;
  try {
    out.faces = detail::rebuild_from(layout_quads, layout_adjacency, static_cast<std::uint32_t>(vq),
                                     static_cast<std::uint32_t>(interior), regions, glue_offsets, glue,
                                     source, limits.max_faces);
  } catch (const Error& e) {
    // The traversal names region, face and corner; the stream's position says where in the file.
    const std::string what = e.what();
    if (what.find("byte offset") != std::string::npos) throw;
    throw Error(e.code(), (what.rfind("polygons section: ", 0) == 0 ? "" : "polygons section: ") + what +
                              " (at byte offset " + std::to_string(dec.offset()) + ")");
  }
  dec.finish();
  out.rest = payload.substr(r.pos() + length);
  out.rest_at = stream_offset + length;
  return out;
}

std::vector<float> polygon_positions(const PolygonStream& stream, std::uint32_t layout_vertices,
                                     std::span<const float> layout_positions,
                                     const std::vector<float>* interior_positions) {
  const InteriorOwners own = interior_owners(stream.faces, layout_vertices);
  const auto interior_owned = static_cast<std::uint32_t>(own.interior_refs.size());
  std::vector<float> decoded;
  const std::vector<float>* interior = interior_positions;
  if (interior) {
    if (!stream.rest.empty())
      fail(std::to_string(stream.rest.size()) +
               " bytes after the stream (the geometry section codes the "
               "interior positions)",
           stream.rest_at);
    if (interior->size() != 3 * std::size_t{interior_owned})
      throw Error(ErrorCode::kInternal, "decode: interior positions do not match the interior vertices");
  } else if (interior_owned == 0) {
    if (!stream.rest.empty())
      fail(std::to_string(stream.rest.size()) + " bytes after the stream, with no interior position",
           stream.rest_at);
  } else {
    if (interior_owned > kMaxSymbolsPerByte * (stream.rest.size() + 8))
      fail("more interior positions than the geometry after the stream can hold", stream.rest_at);
    const std::uint8_t tools = geometry_tools(stream.rest, stream.rest_at);
    if (coding_order(tools) != CodingOrder::kLayout)
      fail("the interior positions are not in layout order (tools bit 1 clear)", stream.rest_at);
    // Before 3.12 no stream here has mirror sources: the bit stays what it was then, reserved.
    if (tools & geometry_tool::kMirror)
      fail("the interior positions use mirror prediction (tools bit 5)", stream.rest_at);
    decoded = decode_geometry(stream.rest, stream.rest_at, chain_stencils(interior_owned), interior_owned);
    interior = &decoded;
  }
  std::vector<float> out(3 * std::size_t{stream.faces.vertex_count});
  for (std::size_t u = 0; u < own.layout_owner.size(); ++u)
    std::copy_n(&layout_positions[3 * std::size_t{own.layout_owner[u]}], 3, &out[3 * u]);
  if (interior)
    std::copy(interior->begin(), interior->end(),
              out.begin() + 3 * static_cast<std::ptrdiff_t>(own.layout_owner.size()));
  return out;
}

}  // namespace qsp
