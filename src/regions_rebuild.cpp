// A polygon mesh rebuilt from its quad layout, region codes and glue (qsp/regions.h): the decoder's side
// of canonical_regions, checking every symbol against what the traversal allows.
#include <string>
#include <tuple>
#include <vector>

#include "qsp/error.h"
#include "qsp/regions.h"
#include "region_source.h"
#include "region_traversal.h"

namespace qsp {
namespace {

[[noreturn]] void bad(const std::string& what) { throw Error(ErrorCode::kFormat, "regions: " + what); }

// The layout's holes: loops by smallest vertex, walked along the exterior half-edges from it.
struct Holes {
  std::vector<std::uint32_t> offsets{0}, vertices;  // loop l: vertices[offsets[l] .. offsets[l+1])
  std::vector<std::uint32_t> loop_next, loop_prev;  // per ref (kInvalid off the holes)
  std::vector<std::uint32_t> loop_of, position;     // per layout ref on a hole (kInvalid off the holes)
  std::uint32_t loops() const { return static_cast<std::uint32_t>(offsets.size() - 1); }
};

Holes layout_holes(const Adjacency& adj, std::uint32_t refs) {
  Holes out;
  out.loop_next.assign(refs, kInvalid);
  out.loop_prev.assign(refs, kInvalid);
  out.loop_of.assign(adj.vertex_count, kInvalid);
  out.position.assign(adj.vertex_count, kInvalid);
  const std::uint32_t first = 4 * adj.face_count;
  std::vector<std::uint8_t> walked(adj.halfedge_count() - first, 0);
  for (std::uint32_t v = 0; v < adj.vertex_count; ++v) {
    const std::uint32_t h = adj.vertex_halfedge[v];
    if (h == kInvalid || !adj.is_exterior(h) || walked[h - first]) continue;
    std::uint32_t x = h;
    do {
      walked[x - first] = 1;
      const std::uint32_t u = adj.origin[x], w = adj.origin[adj.twin[x]];
      out.loop_of[u] = out.loops();
      out.position[u] = static_cast<std::uint32_t>(out.vertices.size() - out.offsets.back());
      out.vertices.push_back(u);
      out.loop_next[u] = w;
      out.loop_prev[w] = u;
      x = adj.exterior_next[x - first];
    } while (x != h);
    out.offsets.push_back(static_cast<std::uint32_t>(out.vertices.size()));
  }
  return out;
}

// Reads one region's symbols for the traversal, naming the region and face in every refusal.
class RegionReader {
 public:
  using Source = detail::RegionSource;
  RegionReader(Source& source, std::uint32_t region, const Holes& holes, std::uint32_t& next_ref,
               std::uint32_t end_ref, std::vector<std::uint32_t>& offsets,
               std::vector<std::uint32_t>& corners, std::uint64_t max_faces)
      : source_(source),
        region_(region),
        holes_(holes),
        next_ref_(next_ref),
        end_ref_(end_ref),
        offsets_(offsets),
        corners_(corners),
        max_faces_(max_faces) {}

  void finish() {
    if (!source_.region_done()) fail("symbols left after its traversal closes");
  }

  std::uint32_t degree(std::uint32_t) {
    const std::uint64_t d = source_.degree();
    if (d == Source::kEnd) fail("its faces end before its traversal does");
    // A face's corners are distinct refs: a larger degree fails at a repeated vertex anyway, after as
    // many symbols as there are refs.
    if (d > end_ref_)
      fail("a face of degree " + std::to_string(d) + " among " + std::to_string(end_ref_) + " vertices");
    degree_ = static_cast<std::uint32_t>(d);
    fresh_face_ = true;
    return degree_;
  }
  std::uint32_t free_vertex() { return fresh(); }
  std::uint32_t corner(std::uint32_t i, const std::vector<std::uint32_t>& face, std::uint32_t follow,
                       std::uint32_t close) {
    corner_ = i;
    if (fresh_face_) {
      for (std::uint32_t v : face) see(v);
      fresh_face_ = false;
    }
    const std::uint32_t v = symbol(i + 1 == degree_, follow, close);
    see(v);
    return v;
  }
  std::uint32_t symbol(bool last, std::uint32_t follow, std::uint32_t close) {
    const std::uint64_t s = source_.corner(last);
    if (s == Source::kEnd) fail("its corners end early");
    switch (s) {
      case static_cast<std::uint64_t>(CornerSymbol::kFollow):
        if (follow == kInvalid) fail("kFollow with no open half-edge at the previous corner");
        return follow;
      case static_cast<std::uint64_t>(CornerSymbol::kClose):
        if (close == kInvalid) fail("kClose with no open half-edge at the first corner");
        return close;
      case static_cast<std::uint64_t>(CornerSymbol::kNew):
        return fresh();
      case static_cast<std::uint64_t>(CornerSymbol::kBoundary): {
        const std::uint64_t a = value(detail::RegionValue::kHoleLoop);
        const std::uint64_t b =
            value(a != 0 ? detail::RegionValue::kHolePosition : detail::RegionValue::kHoleStep);
        if (a != 0) return hole_vertex(a - 1, b);
        if (last_hole_ == kInvalid) fail("kBoundary relative to no hole vertex");
        const std::uint32_t loop = holes_.loop_of[last_hole_];
        const std::uint32_t n = holes_.offsets[loop + 1] - holes_.offsets[loop];
        if (b >= n) fail("kBoundary " + std::to_string(b) + " steps along a loop of " + std::to_string(n));
        return holes_.vertices[holes_.offsets[loop] + (holes_.position[last_hole_] + b) % n];
      }
      case static_cast<std::uint64_t>(CornerSymbol::kInterior): {
        const std::uint64_t back = value(detail::RegionValue::kInteriorBack);
        if (back >= interior_) fail("kInterior " + std::to_string(back) + " past the region's interior");
        return static_cast<std::uint32_t>(next_ref_ - 1 - back);
      }
      default:
        break;
    }
    fail("an unknown corner symbol");
  }
  void listed(const std::vector<std::uint32_t>& face) {
    if (offsets_.size() > max_faces_)
      throw Error(ErrorCode::kLimit, "regions: more faces than the limit " + std::to_string(max_faces_));
    corners_.insert(corners_.end(), face.begin(), face.end());
    offsets_.push_back(static_cast<std::uint32_t>(corners_.size()));
    ++face_;
    corner_ = kInvalid;
  }
  bool open(std::uint32_t i, std::uint32_t) {
    const std::uint64_t x = source_.open(i, degree_);
    if (x == Source::kEnd) fail("its edge flags end early");
    if (x > 1) fail("an edge flag other than 0 or 1");
    return x != 0;
  }
  [[noreturn]] void fail(const std::string& what) {
    std::string where = "region " + std::to_string(region_) + ", face " + std::to_string(face_);
    if (corner_ != kInvalid) where += ", corner " + std::to_string(corner_);
    bad(where + ": " + what);
  }
  [[noreturn]] void fail(const char* what) { fail(std::string(what)); }

  std::uint32_t hole_vertex(std::uint64_t loop, std::uint64_t position) {
    if (loop >= holes_.loops()) fail("loop " + std::to_string(loop) + " out of range");
    if (position >= holes_.offsets[loop + 1] - holes_.offsets[loop])
      fail("position " + std::to_string(position) + " past loop " + std::to_string(loop));
    return holes_.vertices[holes_.offsets[loop] + position];
  }

 private:
  std::uint64_t value(detail::RegionValue kind) {
    const std::uint64_t x = source_.value(kind);
    if (x == Source::kEnd) fail("its values end early");
    return x;
  }
  void see(std::uint32_t v) {
    if (v < holes_.loop_of.size() && holes_.loop_of[v] != kInvalid) last_hole_ = v;
  }
  std::uint32_t fresh() {
    if (next_ref_ == end_ref_) fail("more new vertices than declared");
    ++interior_;
    return next_ref_++;
  }

  Source& source_;
  std::uint32_t region_;
  const Holes& holes_;
  std::uint32_t& next_ref_;
  std::uint32_t end_ref_;
  std::vector<std::uint32_t>& offsets_;
  std::vector<std::uint32_t>& corners_;
  std::uint64_t max_faces_;
  std::uint32_t interior_ = 0, face_ = 0, corner_ = kInvalid, last_hole_ = kInvalid, degree_ = 0;
  bool fresh_face_ = false;
};

}  // namespace

PolygonFaces rebuild_polygons(std::span<const std::uint32_t> layout_quads, const Adjacency& layout_adjacency,
                              const RegionCodes& codes) {
  // Every new vertex is a kNew symbol or a free start: check the declared count before allocating by it.
  std::uint64_t fresh = 0;
  for (const RegionCode& c : codes.regions) {
    fresh += c.start == RegionStart::kFree;
    for (CornerSymbol x : c.corners) fresh += x == CornerSymbol::kNew;
  }
  if (fresh != codes.interior_vertices)
    bad("the codes create " + std::to_string(fresh) + " interior vertices, not the " +
        std::to_string(codes.interior_vertices) + " declared");
  detail::CodesSource source(codes);
  return detail::rebuild_from(layout_quads, layout_adjacency, codes.layout_vertices, codes.interior_vertices,
                              codes.regions.size(), codes.glue_offsets, codes.glue, source,
                              kPolygonSizeLimit);
}

namespace detail {

PolygonFaces rebuild_from(std::span<const std::uint32_t> layout_quads, const Adjacency& layout_adjacency,
                          std::uint32_t layout_vertices, std::uint32_t interior_vertices,
                          std::uint64_t region_count, std::span<const std::uint32_t> glue_offsets,
                          std::span<const std::uint32_t> glue, RegionSource& source,
                          std::uint64_t max_faces) {
  const std::uint32_t vq = layout_vertices;
  if (layout_adjacency.vertex_count != vq ||
      layout_quads.size() != 4 * std::size_t{layout_adjacency.face_count})
    throw Error(ErrorCode::kInternal, "regions: the layout quads and their adjacency disagree");
  if (std::uint64_t{vq} + interior_vertices >= kPolygonSizeLimit)
    bad("more vertices than qsp handles (2^31)");
  if (layout_adjacency.face_count > max_faces)
    throw Error(ErrorCode::kLimit, "regions: more faces than the limit " + std::to_string(max_faces));
  const std::uint32_t refs = vq + interior_vertices;
  // Glue first: the traversal compares vertices by class (their group's first ref). Groups of two or
  // more refs, increasing, groups by first ref, each ref once, every layout ref in a quad.
  if (glue_offsets.empty() || glue_offsets[0] != 0 || glue_offsets.back() != glue.size())
    bad("glue offsets do not cover the glue");
  const std::size_t ng = glue_offsets.size() - 1;
  std::vector<std::uint32_t> head(refs, kInvalid), klass(refs);
  for (std::size_t g = 0; g < ng; ++g) {
    const std::uint32_t b = glue_offsets[g], e = glue_offsets[g + 1];
    const std::string where = "glue group " + std::to_string(g) + ": ";
    if (e > glue.size()) bad(where + "ends past the glue");
    if (e < b || e - b < 2) bad(where + "fewer than two vertices");
    if (g > 0 && glue[b] <= glue[glue_offsets[g - 1]]) bad(where + "groups out of order");
    for (std::uint32_t i = b; i < e; ++i) {
      const std::uint32_t x = glue[i];
      if (x >= refs) bad(where + "vertex " + std::to_string(x) + " out of range");
      if (i > b && x <= glue[i - 1]) bad(where + "vertices out of order");
      if (head[x] != kInvalid) bad(where + "vertex " + std::to_string(x) + " in two groups");
      if (x < vq && layout_adjacency.valence[x] == 0)
        bad(where + "vertex " + std::to_string(x) + " in no face");
      head[x] = glue[b];
    }
  }
  for (std::uint32_t x = 0; x < refs; ++x) klass[x] = head[x] == kInvalid ? x : head[x];

  const Holes holes = layout_holes(layout_adjacency, refs);
  detail::RegionTraversal traversal(holes.loop_next, holes.loop_prev, klass, refs);
  PolygonFaces out;
  out.corners.assign(layout_quads.begin(), layout_quads.end());
  for (std::size_t q = 1; q <= layout_adjacency.face_count; ++q)
    out.face_offsets.push_back(static_cast<std::uint32_t>(4 * q));
  std::uint32_t next_ref = vq;
  StartCode p;
  for (std::uint64_t r = 0; r < region_count; ++r) {
    const StartCode c = source.start();
    RegionReader reader(source, static_cast<std::uint32_t>(r), holes, next_ref, refs, out.face_offsets,
                        out.corners, max_faces);
    if (c.start > RegionStart::kFree) reader.fail("an unknown start");
    std::uint32_t first = 0;
    if (c.start == RegionStart::kFree) {
      if (c.loop != 0 || c.position != 0) reader.fail("a free start with a loop");
    } else {
      first = reader.hole_vertex(c.loop, c.position);
    }
    if (r > 0) {
      if (p.start == RegionStart::kFree && c.start != RegionStart::kFree)
        reader.fail("a start on a hole after a free start");
      if (c.start != RegionStart::kFree &&
          std::make_tuple(c.loop, c.position, c.start) < std::make_tuple(p.loop, p.position, p.start))
        reader.fail("starts out of order");
    }
    traversal.run(reader, c.start, first);
    reader.finish();
    p = c;
  }
  if (next_ref != refs)
    bad("the regions create " + std::to_string(next_ref - vq) + " interior vertices, not the " +
        std::to_string(interior_vertices) + " declared");

  out.ref_vertex.resize(refs);
  for (std::uint32_t x = 0; x < refs; ++x)
    out.ref_vertex[x] = head[x] == kInvalid || head[x] == x ? out.vertex_count++ : out.ref_vertex[head[x]];
  std::vector<std::uint32_t> seen(out.vertex_count, kInvalid);
  const auto nf = static_cast<std::uint32_t>(out.face_offsets.size() - 1);
  for (std::uint32_t f = 0; f < nf; ++f)
    for (std::uint32_t i = out.face_offsets[f]; i < out.face_offsets[f + 1]; ++i) {
      std::uint32_t& v = out.corners[i];
      v = out.ref_vertex[v];
      if (seen[v] == f)
        bad("face " + std::to_string(f) + " repeats vertex " + std::to_string(v) + " once glued");
      seen[v] = f;
    }
  return out;
}

}  // namespace detail

}  // namespace qsp
