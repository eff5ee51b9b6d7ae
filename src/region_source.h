// src/region_source.h (internal): where rebuild_polygons reads the region symbols from, one at a time,
// in the order the traversal asks for them: the RegionCodes structures (qsp/regions.h), or a .qsp's
// polygons section (src/polygon_section.cpp), which decodes each symbol when it is asked for. So the
// section needs no counts of faces, corners or flags: the traversal says when a region ends.
#pragma once

#include <cstdint>
#include <span>

#include "qsp/regions.h"

namespace qsp::detail {

// What a value is (RegionCode::values): a kBoundary's first value (0 or 1 + loop), its second (steps
// along the last hole vertex's loop, or an absolute position on the loop named), a kInterior's back.
enum class RegionValue : std::uint8_t { kHoleLoop, kHoleStep, kHolePosition, kInteriorBack };

// A region's start as RegionCode holds it.
struct StartCode {
  RegionStart start = RegionStart::kFree;
  std::uint64_t loop = 0, position = 0;
};

// Every read returns kEnd when the symbols run out (a stream throws instead); values are otherwise
// unchecked: the reader checks them against the traversal.
class RegionSource {
 public:
  static constexpr std::uint64_t kEnd = std::uint64_t{1} << 40;
  virtual ~RegionSource() = default;
  virtual StartCode start() = 0;  // region r's start, r = 0, 1, ... (called region_count times)
  virtual std::uint64_t degree() = 0;
  // The symbol of a face's corner (a CornerSymbol value, or anything else: refused); `last`: the
  // face's last corner.
  virtual std::uint64_t corner(bool last) = 0;
  virtual std::uint64_t value(RegionValue kind) = 0;
  // Edge `edge` of a face of `degree` corners: 1 if a face lies across it (anything but 0 or 1: refused).
  virtual std::uint64_t open(std::uint32_t edge, std::uint32_t degree) = 0;
  // After a region's traversal closed: false if the source still holds symbols of that region.
  virtual bool region_done() = 0;
};

// RegionCodes as a source.
class CodesSource final : public RegionSource {
 public:
  explicit CodesSource(const RegionCodes& codes) : codes_(codes) {}
  StartCode start() override {
    code_ = &codes_.regions[next_++];
    di_ = ci_ = vi_ = oi_ = 0;
    return {code_->start, code_->loop, code_->position};
  }
  std::uint64_t degree() override { return di_ < code_->degrees.size() ? code_->degrees[di_++] : kEnd; }
  std::uint64_t corner(bool) override {
    return ci_ < code_->corners.size() ? static_cast<std::uint64_t>(code_->corners[ci_++]) : kEnd;
  }
  std::uint64_t value(RegionValue) override {
    return vi_ < code_->values.size() ? code_->values[vi_++] : kEnd;
  }
  std::uint64_t open(std::uint32_t, std::uint32_t) override {
    return oi_ < code_->open.size() ? code_->open[oi_++] : kEnd;
  }
  bool region_done() override {
    return di_ == code_->degrees.size() && ci_ == code_->corners.size() && vi_ == code_->values.size() &&
           oi_ == code_->open.size();
  }

 private:
  const RegionCodes& codes_;
  const RegionCode* code_ = nullptr;
  std::size_t next_ = 0, di_ = 0, ci_ = 0, vi_ = 0, oi_ = 0;
};

// What rebuild_polygons checks and builds, with the symbols from `source`: `region_count` regions over
// `layout_vertices` layout refs and `interior_vertices` declared interior refs, the glue as in
// RegionCodes. Faces (quads included) past `max_faces` are refused with Error(kLimit). Interior refs are
// checked against the declared count as they are created and at the end. Same errors and cost as
// rebuild_polygons otherwise; what `source` throws passes through.
PolygonFaces rebuild_from(std::span<const std::uint32_t> layout_quads, const Adjacency& layout_adjacency,
                          std::uint32_t layout_vertices, std::uint32_t interior_vertices,
                          std::uint64_t region_count, std::span<const std::uint32_t> glue_offsets,
                          std::span<const std::uint32_t> glue, RegionSource& source, std::uint64_t max_faces);

}  // namespace qsp::detail
