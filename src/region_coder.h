// src/region_coder.h (internal): a region of non-quad faces seen from the quad submesh, and its code
// from one start under a (partial) layout numbering: what canonical_regions compares and keeps
// (qsp/regions.h). The traversal itself is region_traversal.h's, shared with the decoder.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "qsp/regions.h"
#include "qsp/submesh.h"
#include "region_traversal.h"

namespace qsp::detail {

// Throws Error(kInternal): an invariant of the region coder failed (a bug, never a wrong result).
[[noreturn]] void regions_internal(const std::string& what);

// The region faces over submesh vertices, and everything about them that no numbering changes.
struct RegionFaces {
  std::span<const std::uint32_t> offsets, vertex;  // vertex: per input corner its submesh vertex
  std::uint32_t layout_vertices = 0;               // submesh vertices below this are quad vertices
  std::vector<std::uint32_t> face_of;              // per input corner
  std::vector<std::uint32_t> region_of;            // per input face: its region, kInvalid for quads
  // Per corner of a region face (as the half-edge to the next corner): the corner of the reverse
  // half-edge in a face of the same region, or kInvalid.
  std::vector<std::uint32_t> twin;
  // Per corner of a region face whose half-edge is glued to a quad's hole half-edge: the hole vertex
  // (a copy of the corner's vertex) that half-edge enters, where an edge start enters; else kInvalid.
  std::vector<std::uint32_t> anchor;
  std::vector<std::uint32_t> loop_next, loop_prev;  // per submesh vertex (kInvalid off the holes)
  std::vector<std::uint32_t> hole_loop;             // per submesh vertex: its submesh loop, or kInvalid
  std::vector<std::uint32_t> loop_length;           // per submesh loop: its edges

  std::uint32_t next(std::uint32_t c) const {
    return c + 1 == offsets[face_of[c] + 1] ? offsets[face_of[c]] : c + 1;
  }
  std::uint32_t degree(std::uint32_t f) const { return offsets[f + 1] - offsets[f]; }
};

// The regions' faces of quad_submesh `s` cut from the polygon arrays with these face offsets.
RegionFaces region_faces(std::span<const std::uint32_t> offsets, const QuadSubmesh& s);

using Bits = std::array<std::uint32_t, 3>;

// Positions as float bits, per submesh vertex (zeros without positions).
struct PositionBits {
  std::span<const float> positions;
  std::span<const std::uint32_t> original;  // per submesh vertex
  Bits operator()(std::uint32_t v) const {
    Bits b{};
    if (!positions.empty()) std::memcpy(b.data(), &positions[3 * std::size_t{original[v]}], 12);
    return b;
  }
};

// The layout numbering so far: the tie search places components one by one.
struct Numbering {
  std::vector<std::uint32_t> layout;    // per quad submesh vertex: layout index, kInvalid if not placed
  std::vector<std::uint32_t> loop_id;   // per submesh loop: canonical loop, kInvalid if not placed
  std::vector<std::uint32_t> position;  // per hole vertex: its position once its loop is placed
};

// One region coded from one start.
struct CodedRegion {
  RegionCode code;
  std::vector<std::uint32_t> interior;     // submesh vertices created, in order
  std::vector<std::uint32_t> face, start;  // per face in traversal order: input face, its first corner
  std::vector<std::uint32_t> key;          // for comparisons (see RegionCoder::code)
  bool determined() const { return key.size() != 1; }
};

// Codes a region from a start under a Numbering: runs the traversal with the region's faces, picking
// for each corner the cheapest symbol that names a copy of its vertex.
class RegionCoder {
 public:
  RegionCoder(const RegionFaces& faces, const QuadSubmesh& s, const Numbering& numbering,
              const PositionBits& bits, std::uint32_t vertex_count)
      : f_(faces),
        s_(s),
        num_(numbering),
        bits_(bits),
        traversal_(faces.loop_next, faces.loop_prev, s.vertex_original,
                   static_cast<std::uint32_t>(s.vertex_original.size())),
        local_(s.vertex_original.size(), 0),
        first_local_(vertex_count, 0),
        listed_copy_(vertex_count, kInvalid),
        reached_(faces.region_of.size(), 0) {}

  // Region `r` from input corner `corner`: for kEdge one whose half-edge is glued to a hole edge (the
  // face is listed from that edge's hole vertex, a copy of the corner's), for kFree any. The key orders
  // codes canonically: (loop, position, start), the streams, the interior vertices' positions, and which
  // interior vertices are copies of one input vertex. With parts of the layout not placed, references
  // into them are kInvalid (and a start there makes the key {kInvalid}: undetermined).
  CodedRegion code(std::uint32_t r, RegionStart start, std::uint32_t corner) {
    out_ = CodedRegion{};
    out_.code.start = start;
    const std::uint32_t first = start == RegionStart::kEdge ? f_.anchor[corner] : f_.vertex[corner];
    if (start == RegionStart::kEdge) {
      out_.code.loop = num_.loop_id[f_.hole_loop[first]];
      out_.code.position = num_.position[first];
      if (out_.code.loop == kInvalid) {
        out_.key = {kInvalid};
        return std::move(out_);
      }
    }
    start_corner_ = corner;
    first_face_ = true;
    last_hole_ = kInvalid;
    traversal_.run(*this, start, first);
    for (std::uint32_t v : out_.interior) local_[v] = 0;
    for (std::uint32_t v : listed_) listed_copy_[s_.vertex_original[v]] = kInvalid;
    listed_.clear();
    for (std::uint32_t g : out_.face) reached_[g] = 0;
    if (out_.face.size() != s_.regions[r].faces.size())
      regions_internal("a region is not connected across its edges");

    const RegionCode& c = out_.code;
    std::vector<std::uint32_t>& k = out_.key;
    k = {c.loop, c.position, static_cast<std::uint32_t>(c.start)};
    auto put = [&k](const auto& stream) {
      k.push_back(static_cast<std::uint32_t>(stream.size()));
      for (auto x : stream) k.push_back(static_cast<std::uint32_t>(x));
    };
    put(c.degrees);
    put(c.corners);
    put(c.values);
    put(c.open);
    for (std::uint32_t v : out_.interior)
      for (std::uint32_t b : bits_(v)) k.push_back(b);
    for (std::uint32_t i = 0; i < out_.interior.size(); ++i) {
      std::uint32_t& copied = first_local_[s_.vertex_original[out_.interior[i]]];
      k.push_back(copied);  // 0, or 1 + the first interior vertex copying the same input vertex
      if (copied == 0) copied = i + 1;
    }
    for (std::uint32_t v : out_.interior) first_local_[s_.vertex_original[v]] = 0;
    return std::move(out_);
  }

  // The traversal's coder interface (region_traversal.h).
  std::uint32_t degree(std::uint32_t gate) {
    const std::uint32_t start = first_face_ ? start_corner_ : record_twin_[gate];
    first_face_ = false;
    face_ = f_.face_of[start];
    first_ = f_.offsets[face_];
    d_ = f_.degree(face_);
    shift_ = start - first_;
    reached_[face_] = 1;
    out_.face.push_back(face_);
    out_.start.push_back(start);
    out_.code.degrees.push_back(d_);
    fresh_face_ = true;
    const auto& listed = traversal_.face();
    for (std::uint32_t i = 0; i < listed.size(); ++i)
      if (original(listed[i]) != original(f_.vertex[at(i)]))
        regions_internal("a face entered where the traversal does not expect it");
    return d_;
  }
  std::uint32_t free_vertex() {
    remember(f_.vertex[start_corner_]);
    return f_.vertex[start_corner_];
  }
  // A candidate wherever it is a copy of the corner's vertex (glue merges them); else a copy already
  // listed in this region, so a vertex is not created twice; else the corner's own copy.
  std::uint32_t corner(std::uint32_t i, const std::vector<std::uint32_t>& face, std::uint32_t follow,
                       std::uint32_t close) {
    if (fresh_face_) {  // the corners listed before the face's first coded one
      for (std::uint32_t v : face) see(v);
      fresh_face_ = false;
    }
    const std::uint32_t actual = f_.vertex[at(i)], k = original(actual);
    RegionCode& c = out_.code;
    std::uint32_t v = actual;
    if (follow != kInvalid && original(follow) == k) {
      c.corners.push_back(CornerSymbol::kFollow);
      v = follow;
    } else if (close != kInvalid && original(close) == k) {
      c.corners.push_back(CornerSymbol::kClose);
      v = close;
    } else {
      if (v >= f_.layout_vertices && local_[v] == 0 && listed_copy_[k] != kInvalid) v = listed_copy_[k];
      if (v >= f_.layout_vertices && local_[v] == 0) {
        c.corners.push_back(CornerSymbol::kNew);
      } else if (v < f_.layout_vertices) {
        c.corners.push_back(CornerSymbol::kBoundary);
        boundary_values(v);
      } else {
        c.corners.push_back(CornerSymbol::kInterior);
        c.values.push_back(static_cast<std::uint32_t>(out_.interior.size()) - local_[v]);
      }
    }
    remember(v);
    see(v);
    return v;
  }
  void listed(const std::vector<std::uint32_t>&) {}
  bool open(std::uint32_t i, std::uint32_t record) {
    const std::uint32_t t = f_.twin[at(i)];
    const bool across = t != kInvalid && !reached_[f_.face_of[t]];
    out_.code.open.push_back(across);
    if (!across) return false;
    reached_[f_.face_of[t]] = 1;
    if (record_twin_.size() <= record) record_twin_.resize(record + 1);
    record_twin_[record] = t;
    return true;
  }
  [[noreturn]] void fail(const char* what) { regions_internal(what); }

 private:
  std::uint32_t at(std::uint32_t i) const { return first_ + (shift_ + i) % d_; }
  std::uint32_t original(std::uint32_t v) const { return s_.vertex_original[v]; }
  void remember(std::uint32_t v) {
    if (listed_copy_[original(v)] == kInvalid) {
      listed_copy_[original(v)] = v;
      listed_.push_back(v);
    }
    if (v < f_.layout_vertices || local_[v] != 0) return;
    out_.interior.push_back(v);
    local_[v] = static_cast<std::uint32_t>(out_.interior.size());
  }
  void see(std::uint32_t v) {
    if (v < f_.layout_vertices && f_.hole_loop[v] != kInvalid) last_hole_ = v;
  }
  // A hole vertex relative to the last one listed (regions.h, RegionCode::values).
  void boundary_values(std::uint32_t v) {
    std::vector<std::uint32_t>& values = out_.code.values;
    const std::uint32_t loop = num_.loop_id[f_.hole_loop[v]];
    if (loop == kInvalid) {
      values.insert(values.end(), {kInvalid, kInvalid});
    } else if (last_hole_ != kInvalid && f_.hole_loop[last_hole_] == f_.hole_loop[v]) {
      const std::uint32_t n = f_.loop_length[f_.hole_loop[v]];
      values.insert(values.end(), {0, (num_.position[v] + n - num_.position[last_hole_]) % n});
    } else {
      values.insert(values.end(), {1 + loop, num_.position[v]});
    }
  }

  const RegionFaces& f_;
  const QuadSubmesh& s_;
  const Numbering& num_;
  const PositionBits& bits_;
  RegionTraversal traversal_;
  std::vector<std::uint32_t> local_;        // per submesh vertex: 1 + its interior index in this run, or 0
  std::vector<std::uint32_t> first_local_;  // per input vertex (scratch for the key)
  std::vector<std::uint32_t> listed_copy_;  // per input vertex: its first copy listed in this run
  std::vector<std::uint32_t> listed_;       // vertices set in listed_copy_
  std::vector<std::uint8_t> reached_;       // per input face: entered or pushed in this run
  std::vector<std::uint32_t> record_twin_;  // per open record pushed: the corner entered through it
  CodedRegion out_;
  std::uint32_t start_corner_ = 0, face_ = 0, first_ = 0, d_ = 0, shift_ = 0, last_hole_ = kInvalid;
  bool first_face_ = true, fresh_face_ = false;
};

// Per input vertex with two or more submesh copies: its copies, increasing.
struct GlueGroups {
  std::vector<std::uint32_t> offsets{0}, members;
  std::uint32_t size() const { return static_cast<std::uint32_t>(offsets.size() - 1); }
};

GlueGroups glue_groups(const QuadSubmesh& s, std::uint32_t vertex_count);

}  // namespace qsp::detail
