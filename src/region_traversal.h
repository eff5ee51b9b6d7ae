// src/region_traversal.h (internal): the traversal of one non-quad region (qsp/regions.h), run by both
// canonical_regions (which knows the faces and picks symbols) and rebuild_polygons (which reads them),
// so the two cannot disagree on a candidate or on the order faces are entered.
//
// State: the open half-edges, each waiting for a face on its other side: the quads' hole half-edges
// (implicit: the one into each hole vertex v comes from loop_next[v]) and the decoded faces' edges that
// closed nothing. Each vertex keeps its open half-edges in and out as stacks (newest on top, the quad's
// at the bottom); a closed one leaves lazily, so every operation is O(1) amortized. Only tops are
// looked at: a corner's candidates, and whether a new edge closes an open one. Vertices are compared by
// class (the input vertex: glue merges every copy of one), so an edge closes the open half-edge of a
// face or quad it is glued to in the input even where rule 4 put its corners on other copies.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "qsp/mesh.h"
#include "qsp/regions.h"

namespace qsp::detail {

// A handle names an open half-edge: a record of a decoded face, or with this bit the quad half-edge into
// the vertex in the low bits.
inline constexpr std::uint32_t kQuadHalfedge = 0x80000000u;

class RegionTraversal {
 public:
  // Vertex ids [0, ids); loop_next / loop_prev: a hole vertex's neighbours along its loop in the
  // exterior direction (kInvalid off the holes); klass: per id its class (equal for copies of one input
  // vertex). ids < 2^31.
  RegionTraversal(std::span<const std::uint32_t> loop_next, std::span<const std::uint32_t> loop_prev,
                  std::span<const std::uint32_t> klass, std::uint32_t ids)
      : loop_next_(loop_next),
        loop_prev_(loop_prev),
        klass_(klass),
        head_in_(ids, kInvalid),
        head_out_(ids, kInvalid),
        quad_closed_(ids, 0),
        in_face_(ids, 0),
        touched_flag_(ids, 0) {}

  std::uint32_t ids() const { return static_cast<std::uint32_t>(head_in_.size()); }
  // The face being listed (its corners so far).
  const std::vector<std::uint32_t>& face() const { return face_; }

  // Runs one region. `first`: for kEdge the hole vertex it starts at (the face enters through the quad
  // half-edge into it); for kFree ignored (coder.free_vertex() gives it).
  // Coder:
  //   std::uint32_t degree(std::uint32_t gate)   the degree of the face entered through `gate`
  //                                               (kInvalid: the first face of a vertex or free start)
  //   std::uint32_t free_vertex()                 a kFree start's first vertex
  //   std::uint32_t corner(std::uint32_t i, const std::vector<std::uint32_t>& face, std::uint32_t follow,
  //                        std::uint32_t close)   the vertex of corner i given the corners before it and
  //                                               the candidates (or kInvalid)
  //   void listed(const std::vector<std::uint32_t>& face)  all its corners, as listed
  //   bool open(std::uint32_t i, std::uint32_t record)  whether a new face lies across edge i (i -> i+1),
  //                                               which closed nothing and is now open as `record`
  //   [[noreturn]] void fail(const char* what)
  template <class Coder>
  void run(Coder& coder, RegionStart start, std::uint32_t first) {
    reset();
    if (start == RegionStart::kEdge) {
      if (first >= ids() || loop_next_[first] == kInvalid) coder.fail("an edge start off the holes");
      face(coder, kQuadHalfedge | first, kInvalid);
    } else {
      face(coder, kInvalid, coder.free_vertex());
    }
    while (!gates_.empty()) {
      const std::uint32_t g = gates_.back();
      gates_.pop_back();
      if (closed_[g]) coder.fail("a face entered through an edge another face closed");
      face(coder, g, kInvalid);
    }
  }

 private:
  std::uint32_t from(std::uint32_t h) const {
    return h & kQuadHalfedge ? loop_next_[h & ~kQuadHalfedge] : from_[h];
  }
  std::uint32_t to(std::uint32_t h) const { return h & kQuadHalfedge ? h & ~kQuadHalfedge : to_[h]; }

  void touch(std::uint32_t v) {
    if (touched_flag_[v]) return;
    touched_flag_[v] = 1;
    touched_.push_back(v);
  }
  void reset() {
    for (std::uint32_t v : touched_) {
      head_in_[v] = head_out_[v] = kInvalid;
      quad_closed_[v] = 0;
      touched_flag_[v] = 0;
    }
    touched_.clear();
    from_.clear();
    to_.clear();
    closed_.clear();
    next_in_.clear();
    next_out_.clear();
    gates_.clear();
  }

  // The newest open half-edge into v (out of v), or kInvalid.
  std::uint32_t top_in(std::uint32_t v) {
    std::uint32_t r = head_in_[v];
    while (r != kInvalid && closed_[r]) r = next_in_[r];
    if (head_in_[v] != r) head_in_[v] = r;
    if (r != kInvalid) return r;
    return loop_next_[v] != kInvalid && !quad_closed_[v] ? kQuadHalfedge | v : kInvalid;
  }
  std::uint32_t top_out(std::uint32_t v) {
    std::uint32_t r = head_out_[v];
    while (r != kInvalid && closed_[r]) r = next_out_[r];
    if (head_out_[v] != r) head_out_[v] = r;
    if (r != kInvalid) return r;
    const std::uint32_t w = loop_prev_[v];  // the quad half-edge v -> w is the one into w
    return w != kInvalid && !quad_closed_[w] ? kQuadHalfedge | w : kInvalid;
  }
  void close(std::uint32_t h) {
    if (h & kQuadHalfedge) {
      touch(h & ~kQuadHalfedge);
      quad_closed_[h & ~kQuadHalfedge] = 1;
    } else {
      closed_[h] = 1;
    }
  }
  std::uint32_t add_open(std::uint32_t u, std::uint32_t w) {
    const auto r = static_cast<std::uint32_t>(from_.size());
    touch(u);
    touch(w);
    from_.push_back(u);
    to_.push_back(w);
    closed_.push_back(0);
    next_out_.push_back(head_out_[u]);
    next_in_.push_back(head_in_[w]);
    head_out_[u] = r;
    head_in_[w] = r;
    return r;
  }

  template <class Coder>
  void face(Coder& coder, std::uint32_t gate, std::uint32_t c0) {
    face_.clear();
    std::uint32_t first_edge = 0;
    if (gate != kInvalid) {
      close(gate);
      face_.push_back(to(gate));
      face_.push_back(from(gate));
      first_edge = 1;
    } else {
      if (c0 >= ids()) coder.fail("a vertex out of range");
      face_.push_back(c0);
    }
    const std::uint32_t d = coder.degree(gate);
    if (d < 3 || d == 4) coder.fail("a face of degree 4 or below 3");
    for (std::uint32_t v : face_) in_face_[v] = 1;
    for (auto i = static_cast<std::uint32_t>(face_.size()); i < d; ++i) {
      const std::uint32_t hf = top_in(face_[i - 1]), hc = top_out(face_[0]);
      const std::uint32_t v =
          coder.corner(i, face_, hf == kInvalid ? kInvalid : from(hf), hc == kInvalid ? kInvalid : to(hc));
      if (v >= ids()) coder.fail("a vertex out of range");
      if (in_face_[v]) coder.fail("a face repeats a vertex");
      in_face_[v] = 1;
      face_.push_back(v);
    }
    for (std::uint32_t v : face_) in_face_[v] = 0;
    coder.listed(face_);
    // Which edges close an open half-edge, all seen before any is closed or opened.
    hits_.clear();
    for (std::uint32_t i = first_edge; i < d; ++i) {
      const std::uint32_t u = face_[i], w = face_[i + 1 == d ? 0 : i + 1];
      std::uint32_t h = top_in(u);
      if (h == kInvalid || klass_[from(h)] != klass_[w]) {
        h = top_out(w);
        if (h != kInvalid && klass_[to(h)] != klass_[u]) h = kInvalid;
      }
      hits_.push_back(h);
    }
    for (std::uint32_t h : hits_)
      if (h != kInvalid) close(h);
    for (std::uint32_t i = first_edge; i < d; ++i) {
      if (hits_[i - first_edge] != kInvalid) continue;
      const std::uint32_t r = add_open(face_[i], face_[i + 1 == d ? 0 : i + 1]);
      if (coder.open(i, r)) gates_.push_back(r);
    }
  }

  std::span<const std::uint32_t> loop_next_, loop_prev_, klass_;
  std::vector<std::uint32_t> head_in_, head_out_;
  std::vector<std::uint8_t> quad_closed_, in_face_, touched_flag_;
  std::vector<std::uint32_t> touched_;
  // Records: open half-edges of decoded faces.
  std::vector<std::uint32_t> from_, to_, next_in_, next_out_;
  std::vector<std::uint8_t> closed_;
  std::vector<std::uint32_t> gates_, face_, hits_;
};

}  // namespace qsp::detail
