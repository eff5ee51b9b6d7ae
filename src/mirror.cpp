// A quad mesh's mirror symmetry (src/mirror.h): propagation from seeds, and the encoder's search.
#include "mirror.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <string>

#include "bytes.h"
#include "qsp/error.h"

namespace qsp {
namespace {

// The propagation, reporting failure as false and a message (the search tries seeds that fail).
class Propagation {
 public:
  Propagation(std::span<const std::uint32_t> quads, const Adjacency& adj)
      : quads_(quads),
        adj_(adj),
        vertex_(adj.vertex_count, kInvalid),
        image_(adj.face_count, kInvalid),
        preimage_(adj.face_count, kInvalid),
        turn_(adj.face_count, 0) {}

  // Adds seed s and what follows from it; false if that fails (why() says how).
  bool add(const MirrorSeed& s) {
    const std::uint32_t nf = adj_.face_count;
    if (s.face >= nf || s.image >= nf || s.turn > 3) return fail("seed out of range");
    const std::size_t first = queue_.size();
    if (!assign(s.face, s.image, s.turn)) return false;
    for (std::size_t q = first; q < queue_.size(); ++q) {
      const std::uint32_t f = queue_[q], g = image_[f], r = turn_[f];
      for (std::uint32_t k = 0; k < 4; ++k) {
        // Edge k of f runs from corner k to k + 1; its image runs back along g's edge (r - k - 1).
        const std::uint32_t t = adj_.twin[4 * f + k], tg = adj_.twin[4 * g + ((r - k - 1) & 3u)];
        if (adj_.is_exterior(t) != adj_.is_exterior(tg))
          return fail("face " + std::to_string(f) + " edge " + std::to_string(k) +
                      " and its image: one on the boundary");
        if (adj_.is_exterior(t)) continue;
        const std::uint32_t k2 = t & 3u, j2 = tg & 3u;
        if (!assign(t >> 2, tg >> 2, (j2 + 1 + k2) & 3u)) return false;
      }
    }
    return true;
  }
  const std::string& why() const { return why_; }
  std::vector<std::uint32_t>& vertices() { return vertex_; }
  const std::vector<std::uint32_t>& faces() const { return queue_; }  // in the order reached
  // Forgets every seed, in the time the faces reached take (the search tries dozens per component).
  void clear() {
    for (const std::uint32_t f : queue_) {
      preimage_[image_[f]] = kInvalid, image_[f] = kInvalid;
      for (std::uint32_t c = 0; c < 4; ++c) vertex_[quads_[4 * f + c]] = kInvalid;
    }
    queue_.clear();
  }

 private:
  bool fail(std::string why) {
    why_ = std::move(why);
    return false;
  }
  bool assign(std::uint32_t f, std::uint32_t g, std::uint32_t r) {
    if (image_[f] != kInvalid) {
      if (image_[f] != g || turn_[f] != r) return fail("face " + std::to_string(f) + " has two images");
      return true;
    }
    if (preimage_[g] != kInvalid) return fail("face " + std::to_string(g) + " is the image of two faces");
    image_[f] = g, turn_[f] = static_cast<std::uint8_t>(r), preimage_[g] = f;
    queue_.push_back(f);
    for (std::uint32_t c = 0; c < 4; ++c) {
      const std::uint32_t v = quads_[4 * f + c], w = quads_[4 * g + ((r - c) & 3u)];
      if (vertex_[v] == kInvalid) {
        vertex_[v] = w;
      } else if (vertex_[v] != w) {
        return fail("vertex " + std::to_string(v) + " has two images");
      }
    }
    return true;
  }
  std::span<const std::uint32_t> quads_;
  const Adjacency& adj_;
  std::vector<std::uint32_t> vertex_, image_, preimage_, queue_;
  std::vector<std::uint8_t> turn_;
  std::string why_;
};

}  // namespace

MirrorMap mirror_vertices(std::span<const std::uint32_t> quads, const Adjacency& adj,
                          std::span<const MirrorSeed> seeds, const std::string& what) {
  if (quads.size() != 4 * std::size_t{adj.face_count})
    throw Error(ErrorCode::kInternal, "mirror: quads and adjacency disagree");
  Propagation p(quads, adj);
  MirrorMap m;
  m.axis.assign(adj.vertex_count, 3);
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    if (seeds[i].axis > 2)
      throw Error(ErrorCode::kFormat, what + ": seed " + std::to_string(i) + ": axis out of range");
    const std::size_t first = p.faces().size();
    if (!p.add(seeds[i]))
      throw Error(ErrorCode::kFormat, what + ": seed " + std::to_string(i) + ": " + p.why());
    for (std::size_t q = first; q < p.faces().size(); ++q)
      for (std::uint32_t k = 0; k < 4; ++k)
        m.axis[quads[4 * std::size_t{p.faces()[q]} + k]] = static_cast<std::uint8_t>(seeds[i].axis);
  }
  m.image = std::move(p.vertices());
  return m;
}

MirrorMap section_mirror(std::string_view payload, std::uint64_t offset, std::span<const std::uint32_t> quads,
                         const Adjacency& adj) {
  return mirror_vertices(quads, adj, decode_symmetry(payload, offset, adj.face_count),
                         "symmetry section (at byte offset " + std::to_string(offset) + ")");
}

std::vector<MirrorSeed> find_mirror(std::span<const std::uint32_t> quads, const Adjacency& adj,
                                    std::span<const float> positions, MirrorMap* found) {
  const std::uint32_t nf = adj.face_count;
  if (found) found->image.assign(adj.vertex_count, kInvalid), found->axis.assign(adj.vertex_count, 3);
  // The images of a component's vertices under a propagation (its faces' corners), or none.
  const auto keep = [&](std::span<const std::uint32_t> reached, const std::vector<std::uint32_t>* image,
                        std::uint32_t axis) {
    if (!found) return;
    for (const std::uint32_t f : reached)
      for (std::uint32_t k = 0; k < 4; ++k) {
        const std::uint32_t v = quads[4 * std::size_t{f} + k];
        found->image[v] = image ? (*image)[v] : kInvalid;
        found->axis[v] = static_cast<std::uint8_t>(image ? axis : 3);
      }
  };
  std::vector<std::vector<std::uint32_t>> faces(adj.component_count);
  for (std::uint32_t f = 0; f < nf; ++f) faces[adj.face_component[f]].push_back(f);
  auto centre = [&](std::uint32_t f) {
    std::array<double, 3> c{};
    for (std::uint32_t k = 0; k < 4; ++k)
      for (std::size_t b = 0; b < 3; ++b) c[b] += positions[3 * std::size_t{quads[4 * f + k]} + b] / 4.0;
    return c;
  };
  std::vector<MirrorSeed> seeds;
  Propagation prop(quads, adj);                        // cleared between tries
  std::vector<std::pair<double, std::uint32_t>> near;  // (distance, face) of one component
  std::vector<std::array<double, 3>> centres;          // of one component's faces
  constexpr std::size_t kTries = 4;                    // faces nearest the reflected centre
  for (const std::vector<std::uint32_t>& comp : faces) {
    double lo = HUGE_VAL, hi = -HUGE_VAL, extent = 0;
    std::array<double, 3> blo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, bhi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (const std::uint32_t f : comp)
      for (std::uint32_t k = 0; k < 4; ++k)
        for (std::size_t b = 0; b < 3; ++b) {
          const double x = positions[3 * std::size_t{quads[4 * f + k]} + b];
          blo[b] = std::min(blo[b], x), bhi[b] = std::max(bhi[b], x);
        }
    for (std::size_t b = 0; b < 3; ++b) extent = std::max(extent, bhi[b] - blo[b]);
    if (!(extent > 0)) continue;
    double best = HUGE_VAL;
    MirrorSeed chosen;
    const double tolerance = 0.0004 * extent * extent;  // of the mean squared distance
    centres.clear();
    for (const std::uint32_t f : comp) centres.push_back(centre(f));
    for (std::size_t a = 0; a < 3; ++a) {
      lo = blo[a], hi = bhi[a];
      auto reflect = [&](std::array<double, 3> p) {
        p[a] = lo + hi - p[a];
        return p;
      };
      auto dist2 = [](const std::array<double, 3>& p, const std::array<double, 3>& q) {
        return (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
      };
      const std::uint32_t f0 = comp.front();
      const std::array<double, 3> target = reflect(centre(f0));
      near.clear();
      for (std::size_t i = 0; i < comp.size(); ++i) {
        const double d = dist2(centres[i], target);
        near.emplace_back(std::isnan(d) ? HUGE_VAL : d, comp[i]);  // a strict order for the sort
      }
      const std::size_t n = std::min(kTries, near.size());
      std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(n), near.end());
      // Each nearby face in each turn, by how far its corners lie from f0's reflected ones; the first
      // that is an automorphism is the axis's (a propagation costs the component, a refusal little).
      std::vector<std::pair<double, MirrorSeed>> tries;
      for (std::size_t i = 0; i < n; ++i)
        for (std::uint32_t r = 0; r < 4; ++r) {
          double d = 0;
          for (std::uint32_t k = 0; k < 4; ++k) {
            std::array<double, 3> p{}, q{};
            for (std::size_t b = 0; b < 3; ++b) {
              p[b] = positions[3 * std::size_t{quads[4 * f0 + k]} + b];
              q[b] = positions[3 * std::size_t{quads[4 * near[i].second + ((r - k) & 3u)]} + b];
            }
            d += dist2(reflect(p), q);
          }
          tries.push_back({std::isnan(d) ? HUGE_VAL : d,
                           MirrorSeed{f0, near[i].second, r, static_cast<std::uint32_t>(a)}});
        }
      std::stable_sort(tries.begin(), tries.end(),
                       [](const auto& x, const auto& y) { return x.first < y.first; });
      // Not this axis where even the nearest face's corners lie far from the reflected ones (a
      // propagation would cost the whole component).
      if (tries.empty() || tries.front().first > 4 * 16 * tolerance) continue;
      for (const auto& t : tries) {
        prop.clear();
        if (!prop.add(t.second)) continue;
        double cost = 0;
        std::uint64_t count = 0;
        const std::vector<std::uint32_t>& image = prop.vertices();
        for (const std::uint32_t f : prop.faces()) {  // each face's first corner: about each vertex once
          const std::uint32_t v = quads[4 * f];
          std::array<double, 3> pv{}, pw{};
          for (std::size_t b = 0; b < 3; ++b)
            pv[b] = positions[3 * std::size_t{v} + b], pw[b] = positions[3 * std::size_t{image[v]} + b];
          cost += dist2(reflect(pv), pw), ++count;
        }
        cost /= static_cast<double>(count);
        if (cost < best) best = cost, chosen = t.second, keep(prop.faces(), &image, t.second.axis);
        break;
      }
    }
    // A mirror whose images lie within 2% of the component's size of the reflected vertices (rms).
    // (best stays infinite where no seed was an automorphism, or a coordinate is not finite.)
    if (std::isfinite(best) && best <= tolerance)
      seeds.push_back(chosen);
    else if (std::isfinite(best))
      keep(comp, nullptr, 3);  // an image kept above, for a mirror not kept
  }
  return seeds;
}

void set_mirror_sources(std::vector<Stencil>& stencil, const std::vector<std::uint32_t>& coding,
                        const MirrorMap& mirror) {
  const auto n = static_cast<std::uint32_t>(mirror.image.size());
  std::vector<std::uint32_t> position(n);
  for (std::uint32_t k = 0; k < n; ++k) position[coding.empty() ? k : coding[k]] = k;
  for (std::uint32_t k = 0; k < n && k < stencil.size(); ++k) {
    const std::uint32_t v = coding.empty() ? k : coding[k], w = mirror.image[v];
    if (w == kInvalid || w == v || position[w] >= k) continue;
    stencil[k].mirror = position[w];
    stencil[k].mirror_axis = mirror.axis[v];
  }
}

std::string encode_symmetry(std::span<const MirrorSeed> seeds) {
  std::string out;
  put_varint(out, seeds.size());
  for (const MirrorSeed& s : seeds) {
    put_varint(out, s.face);
    put_varint(out, s.image);
    put_u8(out, static_cast<std::uint8_t>(s.turn | s.axis << 2));
  }
  return out;
}

std::vector<MirrorSeed> decode_symmetry(std::string_view payload, std::uint64_t base_offset,
                                        std::uint32_t face_count) {
  ByteReader in(payload, base_offset, "symmetry section");
  const std::uint64_t count_at = in.offset();
  const std::uint64_t n = in.varint("seed count");
  if (n > face_count || n > in.left() / 3) in.fail_at("seed count exceeds the faces or the data", count_at);
  std::vector<MirrorSeed> seeds(n);
  for (MirrorSeed& s : seeds) {
    const std::uint64_t at = in.offset();
    const std::uint64_t f = in.varint("seed face"), g = in.varint("seed image");
    if (f >= face_count || g >= face_count) in.fail_at("seed face out of range", at);
    const std::uint64_t byte_at = in.offset();
    const std::uint8_t b = in.u8("seed turn and axis");
    if ((b >> 2) > 2) in.fail_at("seed axis out of range, or reserved bits set", byte_at);
    s = {static_cast<std::uint32_t>(f), static_cast<std::uint32_t>(g), b & 3u,
         static_cast<std::uint32_t>(b >> 2)};
  }
  if (in.left() != 0) in.fail_at("bytes after the seeds", in.offset());
  return seeds;
}

}  // namespace qsp
