// The canonical codes of a polygon mesh's non-quad regions and vertex glue against its quad submesh's
// canonical layout (qsp/regions.h, docs/polygon_meshes.md).
#include "qsp/regions.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <numeric>
#include <optional>
#include <string>
#include <tuple>
#include <type_traits>

#include "qsp/error.h"
#include "qsp/partition.h"
#include "region_coder.h"

namespace qsp {
namespace {

using detail::Bits;
using detail::CodedRegion;
using detail::GlueGroups;
using detail::Numbering;
using detail::PositionBits;
using detail::RegionCoder;
using detail::RegionFaces;

[[noreturn]] void internal(const std::string& what) { detail::regions_internal(what); }

// What the tie search compares for one candidate: the codes of the regions touching the component
// placed (references to components not yet placed left open), sorted, then the glue groups touching it
// as sorted member descriptions, sorted.
struct TieKey {
  std::vector<std::vector<std::uint32_t>> regions, glue;
  auto operator<=>(const TieKey&) const = default;
};

// A quad component's place in the canonical order: which component, from which of its tied starts
// (kInvalid: the one canonicalize chose).
struct Choice {
  std::uint32_t comp = 0, start = kInvalid;
  bool operator==(const Choice&) const = default;
};

// Tie states kept side by side while tied choices cannot be told apart yet.
inline constexpr std::size_t kTieStates = 16;

class Canonicalizer {
 public:
  Canonicalizer(std::span<const std::uint32_t> offsets, std::span<const float> positions,
                std::uint32_t vertex_count, const QuadSubmesh& s, CanonicalMesh& quads)
      : s_(s),
        cm_(quads),
        faces_(detail::region_faces(offsets, s)),
        bits_{positions, s.vertex_original},
        glue_(detail::glue_groups(s, vertex_count)),
        coder_(faces_, s, num_, bits_, vertex_count),
        vertex_count_(vertex_count) {
    vq_ = faces_.layout_vertices;
    ids_ = static_cast<std::uint32_t>(s.vertex_original.size());
    budget_ = std::uint64_t{kRegionTieCap} * (offsets.back() + ids_) + kRegionTieFloor;
    num_.layout.assign(vq_, kInvalid);
    num_.loop_id.assign(s.loop_halfedge.size(), kInvalid);
    num_.position.assign(vq_, kInvalid);
    scratch_rank_.assign(ids_, kInvalid);
    scratch_index_.assign(ids_, 0);
    classify();
  }

  CanonicalRegions run() {
    code_free_regions();
    const std::vector<Choice> chosen = choose_quad_ties();
    CanonicalRegions out = assemble();
    std::vector<CanonicalComponent> components;
    for (const Choice& c : chosen) {
      CanonicalComponent cc = std::move(cm_.components[c.comp]);
      if (c.start != kInvalid) {
        cc.part = canonical_from_start(s_.adjacency, cc, c.start);
        cc.map = layout_to_mesh(cc.part, s_.adjacency);
      }
      components.push_back(std::move(cc));
    }
    cm_.components = std::move(components);
    fill_maps(out);
    out.quads = std::move(cm_);
    return out;
  }

 private:
  // Regions touching the holes, the components each touches, glue per component, step bases.
  void classify() {
    const auto nr = static_cast<std::uint32_t>(s_.regions.size());
    const auto nk = static_cast<std::uint32_t>(cm_.components.size());
    comp_of_.assign(vq_, kInvalid);
    loops_of_.assign(nk, 0);
    for (std::uint32_t k = 0; k < nk; ++k)
      for (std::uint32_t v : cm_.components[k].map.vertex) {
        if (v >= vq_ || comp_of_[v] != kInvalid)
          internal("the canonical layout does not cover the quad submesh");
        comp_of_[v] = k;
      }
    for (std::uint32_t l = 0; l < s_.loop_halfedge.size(); ++l) {
      const std::uint32_t v = s_.adjacency.origin[s_.loop_halfedge[l]];
      if (comp_of_[v] == kInvalid) internal("a hole off the canonical layout");
      ++loops_of_[comp_of_[v]];
    }
    touching_regions_.assign(nk, {});
    touching_glue_.assign(nk, {});
    boundary_.assign(nr, 0);
    interior_region_.assign(ids_, kInvalid);
    std::vector<std::uint32_t> stamp(nk, kInvalid);
    for (std::uint32_t r = 0; r < nr; ++r) {
      for (std::uint32_t v : s_.regions[r].interior) interior_region_[v] = r;
      bool anchored = false;
      for (std::uint32_t f : s_.regions[r].faces)
        for (std::uint32_t c = faces_.offsets[f]; c < faces_.offsets[f + 1]; ++c) {
          anchored = anchored || faces_.anchor[c] != kInvalid;
          const std::uint32_t v = faces_.vertex[c];
          if (v >= vq_) continue;
          if (comp_of_[v] == kInvalid || faces_.hole_loop[v] == kInvalid)
            internal("a non-quad face touches a quad vertex off the holes");
          boundary_[r] = 1;
          if (stamp[comp_of_[v]] == r) continue;
          stamp[comp_of_[v]] = r;
          touching_regions_[comp_of_[v]].push_back(r);
        }
      if (boundary_[r] && !anchored) internal("a region on a hole has no face glued to a quad");
    }
    std::fill(stamp.begin(), stamp.end(), kInvalid);
    for (std::uint32_t g = 0; g < glue_.size(); ++g)
      for (std::uint32_t i = glue_.offsets[g]; i < glue_.offsets[g + 1]; ++i) {
        const std::uint32_t v = glue_.members[i];
        if (v >= vq_ || comp_of_[v] == kInvalid || stamp[comp_of_[v]] == g) continue;
        stamp[comp_of_[v]] = g;
        touching_glue_[comp_of_[v]].push_back(g);
      }
  }

  // The smallest of the codes from `candidates` by key (kRegionTieCap at most; the first on a tie).
  template <class Try>
  CodedRegion smallest(const std::vector<std::uint32_t>& candidates, Try code) {
    CodedRegion best = code(candidates[0]);
    for (std::size_t i = 1; i < candidates.size() && i < kRegionTieCap; ++i) {
      CodedRegion c = code(candidates[i]);
      if (c.key < best.key) best = std::move(c);
    }
    return best;
  }

  // Region corners by a key (`key(c)` returns nullopt for corners that are no candidate): the tied
  // smallest, in input order.
  template <class Key>
  std::vector<std::uint32_t> smallest_corners(std::uint32_t r, Key key) {
    std::optional<std::remove_cvref_t<decltype(*key(0))>> best;
    std::vector<std::uint32_t> tied;
    for (std::uint32_t f : s_.regions[r].faces)
      for (std::uint32_t c = faces_.offsets[f]; c < faces_.offsets[f + 1]; ++c) {
        const auto k = key(c);
        if (!k) continue;
        if (!best || *k < *best) {
          best = *k;
          tied.assign(1, c);
        } else if (*k == *best) {
          tied.push_back(c);
        }
      }
    return tied;
  }

  // A region with no quad vertex starts at the corner with the smallest position, then the smallest
  // position at the next corner; corners tied on both are compared by the codes they give. Free regions
  // are ordered by that start, then by code.
  void code_free_regions() {
    std::vector<std::tuple<std::vector<std::uint32_t>, std::uint32_t, std::uint32_t>> order;
    std::vector<CodedRegion> coded;
    for (std::uint32_t r = 0; r < s_.regions.size(); ++r) {
      if (boundary_[r]) continue;
      const std::vector<std::uint32_t> tied = smallest_corners(r, [&](std::uint32_t c) {
        return std::optional(std::pair(bits_(faces_.vertex[c]), bits_(faces_.vertex[faces_.next(c)])));
      });
      coded.push_back(smallest(tied, [&](std::uint32_t c) { return coder_.code(r, RegionStart::kFree, c); }));
      std::vector<std::uint32_t> key;
      for (std::uint32_t c : {tied[0], faces_.next(tied[0])})
        for (std::uint32_t b : bits_(faces_.vertex[c])) key.push_back(b);
      key.insert(key.end(), coded.back().key.begin(), coded.back().key.end());
      order.emplace_back(std::move(key), s_.regions[r].faces[0],
                         static_cast<std::uint32_t>(coded.size() - 1));
    }
    std::sort(order.begin(), order.end());
    free_local_.assign(ids_, kInvalid);
    free_region_rank_.assign(s_.regions.size(), kInvalid);
    for (std::uint32_t rank = 0; rank < order.size(); ++rank) {
      CodedRegion& c = coded[std::get<2>(order[rank])];
      for (std::uint32_t i = 0; i < c.interior.size(); ++i) free_local_[c.interior[i]] = i;
      free_region_rank_[faces_.region_of[c.face[0]]] = rank;
      free_.push_back(std::move(c));
    }
  }

  // A region on the holes, under the numbering so far: through its smallest hole edge (loop, position);
  // corners glued to that one edge (a cut edge) compared by code. Undetermined while that edge's
  // component is not placed.
  CodedRegion boundary_code(std::uint32_t r) {
    const std::vector<std::uint32_t> tied = smallest_corners(r, [&](std::uint32_t c) {
      const std::uint32_t v = faces_.anchor[c];
      const std::uint32_t loop = v == kInvalid ? kInvalid : num_.loop_id[faces_.hole_loop[v]];
      return loop == kInvalid ? std::nullopt : std::optional(std::pair(loop, num_.position[v]));
    });
    if (tied.empty()) {
      CodedRegion undetermined;
      undetermined.key = {kInvalid};
      return undetermined;
    }
    return smallest(tied, [&](std::uint32_t c) { return coder_.code(r, RegionStart::kEdge, c); });
  }

  std::uint32_t region_corners(std::uint32_t r) const {
    std::uint32_t n = 0;
    for (std::uint32_t f : s_.regions[r].faces) n += faces_.degree(f);
    return n;
  }

  // Numbers a component's layout vertices from `base` and its loops from `loops` (by smallest layout
  // vertex, position 0 there, along the exterior half-edges).
  void place(const std::vector<std::uint32_t>& layout, std::uint32_t base, std::uint32_t loops) {
    for (std::uint32_t i = 0; i < layout.size(); ++i) num_.layout[layout[i]] = base + i;
    for (std::uint32_t v : layout) {
      const std::uint32_t l = faces_.hole_loop[v];
      if (l == kInvalid || num_.loop_id[l] != kInvalid) continue;
      num_.loop_id[l] = loops++;
      std::uint32_t w = v, p = 0;
      do {
        num_.position[w] = p++;
        w = faces_.loop_next[w];
      } while (w != v);
    }
  }
  // Any order of the component's vertices will do.
  void unplace(std::uint32_t comp) {
    work_ += cm_.components[comp].map.vertex.size();
    for (std::uint32_t v : cm_.components[comp].map.vertex) {
      num_.layout[v] = kInvalid;
      if (faces_.hole_loop[v] != kInvalid) num_.loop_id[faces_.hole_loop[v]] = kInvalid;
    }
  }
  void place(const Choice& c, std::uint32_t step) {
    const CanonicalComponent& cc = cm_.components[c.comp];
    work_ += cc.map.vertex.size();
    if (c.start == kInvalid) {
      place(cc.map.vertex, step_base_[step], step_loops_[step]);
      return;
    }
    const LayoutMap m = layout_to_mesh(canonical_from_start(s_.adjacency, cc, c.start), s_.adjacency);
    work_ += m.vertex.size();
    place(m.vertex, step_base_[step], step_loops_[step]);
  }

  bool same_positions(const std::vector<std::uint32_t>& x, const std::vector<std::uint32_t>& y) const {
    if (x.size() != y.size()) return false;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (x[i] != y[i] && bits_(x[i]) != bits_(y[i])) return false;
    return true;
  }

  // The other starts of component k that give its code and the same positions in layout order (the
  // ties canonicalize leaves to the input's numbering), kRegionTieCap - 1 at most.
  const std::vector<std::uint32_t>& tied_starts(std::uint32_t k) {
    auto& cached = tied_[k];
    if (cached.first) return cached.second;
    cached.first = true;
    const CanonicalComponent& cc = cm_.components[k];
    const bool structured = cc.part.kind == ComponentKind::kAnnulus || cc.part.kind == ComponentKind::kTorus;
    const std::uint32_t own = structured ? cc.part.anchor_halfedge : 0;
    const Bits first = bits_(cc.map.vertex[0]);
    for (std::uint32_t t : canonical_starts(s_.adjacency, cc)) {
      if (t == own || cached.second.size() + 1 >= kRegionTieCap || work_ >= budget_) continue;
      const Schematic& sch = cc.part.schematic;
      const std::uint32_t origin = structured ? s_.adjacency.origin[t] : sch.vertex_mesh[sch.dart_vertex[t]];
      if (bits_(origin) != first) continue;
      const LayoutMap m = layout_to_mesh(canonical_from_start(s_.adjacency, cc, t), s_.adjacency);
      work_ += m.vertex.size();
      if (same_positions(m.vertex, cc.map.vertex)) cached.second.push_back(t);
    }
    return cached.second;
  }

  TieKey tie_key(std::uint32_t k) {
    TieKey key;
    std::vector<CodedRegion> coded;
    for (std::uint32_t r : touching_regions_[k]) {
      coded.push_back(boundary_code(r));
      work_ += region_corners(r);
    }
    std::vector<std::uint32_t> order(coded.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return coded[a].key < coded[b].key; });
    std::vector<std::uint32_t> rank(coded.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) {
      rank[order[i]] = i;
      key.regions.push_back(coded[order[i]].key);
    }
    // Interior vertices of the regions coded here: (rank, index).
    for (std::uint32_t i = 0; i < coded.size(); ++i)
      for (std::uint32_t j = 0; j < coded[i].interior.size(); ++j) {
        scratch_rank_[coded[i].interior[j]] = rank[i];
        scratch_index_[coded[i].interior[j]] = j;
      }
    for (std::uint32_t g : touching_glue_[k]) {
      work_ += glue_.offsets[g + 1] - glue_.offsets[g];
      std::vector<std::array<std::uint32_t, 3>> d;
      for (std::uint32_t i = glue_.offsets[g]; i < glue_.offsets[g + 1]; ++i) {
        const std::uint32_t v = glue_.members[i];
        if (v < vq_) {
          d.push_back(num_.layout[v] != kInvalid ? std::array<std::uint32_t, 3>{0, num_.layout[v], 0}
                                                 : std::array<std::uint32_t, 3>{1, 0, 0});
        } else if (free_local_[v] != kInvalid) {
          d.push_back({4, free_region_rank_[interior_region_[v]], free_local_[v]});
        } else if (scratch_rank_[v] != kInvalid) {
          d.push_back({2, scratch_rank_[v], scratch_index_[v]});
        } else {
          d.push_back({3, 0, 0});
        }
      }
      std::sort(d.begin(), d.end());
      std::vector<std::uint32_t> flat;
      for (const auto& x : d) flat.insert(flat.end(), x.begin(), x.end());
      key.glue.push_back(std::move(flat));
    }
    std::sort(key.glue.begin(), key.glue.end());
    for (const CodedRegion& c : coded)
      for (std::uint32_t v : c.interior) scratch_rank_[v] = kInvalid;
    return key;
  }

  bool identical(std::uint32_t a, std::uint32_t b) const {
    const CanonicalComponent &x = cm_.components[a], &y = cm_.components[b];
    return x.code == y.code && same_positions(x.map.vertex, y.map.vertex);
  }

  // Makes the numbering hold `committed` + `suffix` (committed is always placed).
  void hold(const std::vector<Choice>& suffix) {
    const auto base = static_cast<std::uint32_t>(committed_.size());
    for (std::size_t j = 0; j < held_.size(); ++j)
      if (j >= suffix.size() || !(held_[j] == suffix[j])) unplace(held_[j].comp);
    for (std::size_t j = 0; j < suffix.size(); ++j)
      if (j >= held_.size() || !(held_[j] == suffix[j]))
        place(suffix[j], base + static_cast<std::uint32_t>(j));
    held_ = suffix;
  }

  // canonicalize leaves two choices to the input's numbering: among roots of a component that tie on
  // topology and positions, and the order of components equal in both. Both change nothing in the quad
  // submesh's bytes but may change the regions' and glue's. Components are placed in canonical order;
  // each place goes to the candidates (a tied component, a tied root) whose TieKey is smallest. Choices
  // still tied are kept side by side (kTieStates at most) until a later place tells them apart, and
  // at the end by the whole codes. Returns the choice per place.
  std::vector<Choice> choose_quad_ties() {
    const auto nk = static_cast<std::uint32_t>(cm_.components.size());
    tied_.assign(nk, {});
    std::vector<std::uint32_t> run_start(nk), run_end(nk);
    for (std::uint32_t k = 0; k < nk;) {
      std::uint32_t e = k + 1;
      while (e < nk && identical(e - 1, e)) ++e;
      for (std::uint32_t m = k; m < e; ++m) run_start[m] = k, run_end[m] = e;
      k = e;
    }
    step_base_.assign(nk + 1, 0);
    step_loops_.assign(nk + 1, 0);
    for (std::uint32_t k = 0; k < nk; ++k) {
      step_base_[k + 1] = step_base_[k] + static_cast<std::uint32_t>(cm_.components[k].map.vertex.size());
      step_loops_[k + 1] = step_loops_[k] + loops_of_[k];
    }
    std::uint32_t unreferenced = step_base_[nk];
    for (std::uint32_t v : cm_.unreferenced) {
      if (v >= vq_ || num_.layout[v] != kInvalid || comp_of_[v] != kInvalid)
        internal("an unreferenced vertex is also in a face");
      num_.layout[v] = unreferenced++;
    }
    if (unreferenced != vq_) internal("the canonical layout does not cover the quad submesh");
    std::vector<std::uint8_t> used(nk, 0);  // by a committed choice
    // Per run (at its start): whether a region or glue group touches it; no free component below.
    std::vector<std::uint8_t> run_touched(nk, 0);
    std::vector<std::uint32_t> first_free(nk);
    for (std::uint32_t m = 0; m < nk; ++m) {
      first_free[m] = m;
      run_touched[run_start[m]] |= !touching_regions_[m].empty() || !touching_glue_[m].empty();
    }
    std::vector<std::vector<Choice>> states(1), next;
    for (std::uint32_t k = 0; k < nk; ++k) {
      const std::uint32_t a = run_start[k], e = run_end[k];
      // Past the budget every place takes its run's first free component in canonicalize's order, so a
      // hostile run of thousands of tied components costs its size (regions.h, kRegionTieCap).
      if (work_ >= budget_) {
        if (states.size() > 1 || !states[0].empty()) {
          states.resize(1);
          commit(states, used);
        }
        std::uint32_t& m = first_free[a];
        while (used[m]) ++m;
        states[0].push_back({m, kInvalid});
        commit(states, used);
        continue;
      }
      next.clear();
      TieKey best;
      for (const std::vector<Choice>& state : states) {
        std::vector<Choice> cands;
        for (std::uint32_t m = first_free[a]; m < e; ++m) {
          work_ += 1 + state.size();
          if (used[m] || std::find_if(state.begin(), state.end(),
                                      [m](const Choice& c) { return c.comp == m; }) != state.end())
            continue;
          cands.push_back({m, kInvalid});
          if (!run_touched[a] || work_ >= budget_) break;
          for (std::uint32_t t : tied_starts(m)) cands.push_back({m, t});
        }
        if (cands.size() == 1 && states.size() == 1) {
          next.push_back(state);
          next.back().push_back(cands[0]);
          break;
        }
        hold(state);
        for (const Choice& c : cands) {
          if (!next.empty() && work_ >= budget_) break;  // the best so far: deterministic for this input
          place(c, k);
          TieKey key = tie_key(c.comp);
          unplace(c.comp);
          const bool less = next.empty() || key < best;
          if (less) next.clear(), best = std::move(key);
          if (less || (key == best && next.size() < kTieStates)) {
            next.push_back(state);
            next.back().push_back(c);
          }
        }
      }
      states.swap(next);
      if (states.size() == 1) commit(states, used);
      while (first_free[a] < e && used[first_free[a]]) ++first_free[a];
    }
    if (states.size() > 1) {  // still tied: the whole codes decide
      std::size_t best = 0;
      std::vector<std::uint32_t> best_flat;
      for (std::size_t i = 0; i < states.size(); ++i) {
        hold(states[i]);
        std::vector<std::uint32_t> f = flat(assemble());
        if (i == 0 || f < best_flat) best = i, best_flat = std::move(f);
      }
      states = {states[best]};
      commit(states, used);
    }
    return std::move(committed_);
  }

  void commit(std::vector<std::vector<Choice>>& states, std::vector<std::uint8_t>& used) {
    hold(states[0]);
    for (const Choice& c : states[0]) {
      committed_.push_back(c);
      used[c.comp] = 1;
    }
    held_.clear();
    states.assign(1, {});
  }

  // Everything but the maps, from the numbering as it stands.
  CanonicalRegions assemble() {
    // Regions on the holes by key (then by smallest face: identical regions), then the free ones.
    std::vector<CodedRegion> coded;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> order;  // (first face, index)
    for (std::uint32_t r = 0; r < s_.regions.size(); ++r) {
      if (!boundary_[r]) continue;
      coded.push_back(boundary_code(r));
      if (!coded.back().determined()) internal("a region's start is undetermined");
      order.emplace_back(s_.regions[r].faces[0], static_cast<std::uint32_t>(coded.size() - 1));
    }
    std::sort(order.begin(), order.end(), [&](const auto& a, const auto& b) {
      return std::tie(coded[a.second].key, a.first) < std::tie(coded[b.second].key, b.first);
    });
    regions_.clear();
    for (const auto& o : order) regions_.push_back(std::move(coded[o.second]));
    for (const CodedRegion& c : free_) regions_.push_back(c);

    CanonicalRegions out;
    RegionCodes& codes = out.codes;
    codes.layout_vertices = vq_;
    ref_original_.assign(vq_, 0);  // per ref: its input vertex
    for (std::uint32_t v = 0; v < vq_; ++v) ref_original_[num_.layout[v]] = s_.vertex_original[v];
    for (CodedRegion& c : regions_) {
      for (std::uint32_t v : c.interior) {
        ref_original_.push_back(s_.vertex_original[v]);
        out.interior_original.push_back(s_.vertex_original[v]);
      }
      codes.regions.push_back(c.code);
    }
    const auto nrefs = static_cast<std::uint32_t>(ref_original_.size());
    codes.interior_vertices = nrefs - vq_;

    // Glue: the refs of each input vertex with two or more, increasing, groups by their first ref.
    std::vector<std::uint32_t> start(vertex_count_ + 1, 0), by_original(nrefs);
    head_.assign(nrefs, kInvalid);
    for (std::uint32_t v : ref_original_) ++start[v + 1];
    for (std::uint32_t v = 0; v < vertex_count_; ++v) start[v + 1] += start[v];
    {
      std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
      for (std::uint32_t x = 0; x < nrefs; ++x) by_original[fill[ref_original_[x]]++] = x;
    }
    for (std::uint32_t x = 0; x < nrefs; ++x) {
      const std::uint32_t v = ref_original_[x];
      if (start[v + 1] - start[v] < 2 || by_original[start[v]] != x) continue;
      for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) {
        head_[by_original[i]] = x;
        codes.glue.push_back(by_original[i]);
      }
      codes.glue_offsets.push_back(static_cast<std::uint32_t>(codes.glue.size()));
    }
    return out;
  }

  // The codes and the interior positions, for comparing two whole outcomes.
  std::vector<std::uint32_t> flat(const CanonicalRegions& c) const {
    std::vector<std::uint32_t> out;
    for (const CodedRegion& r : regions_) out.insert(out.end(), r.key.begin(), r.key.end());
    out.insert(out.end(), c.codes.glue_offsets.begin(), c.codes.glue_offsets.end());
    out.insert(out.end(), c.codes.glue.begin(), c.codes.glue.end());
    return out;
  }

  // The input's vertices and faces in what rebuild_polygons gives (after assemble and the final order).
  void fill_maps(CanonicalRegions& out) {
    const auto nrefs = static_cast<std::uint32_t>(ref_original_.size());
    std::vector<std::uint32_t> final_vertex(nrefs);
    std::uint32_t nv = 0;
    for (std::uint32_t x = 0; x < nrefs; ++x)
      final_vertex[x] = head_[x] == kInvalid || head_[x] == x ? nv++ : final_vertex[head_[x]];
    out.vertex.assign(vertex_count_, kInvalid);
    for (std::uint32_t x = 0; x < nrefs; ++x) out.vertex[ref_original_[x]] = final_vertex[x];
    const auto nf = static_cast<std::uint32_t>(faces_.region_of.size());
    out.face.assign(nf, kInvalid);
    out.rotation.assign(nf, 0);
    std::uint32_t face = 0;
    for (const CanonicalComponent& cc : cm_.components)
      for (std::uint32_t i = 0; i < cc.map.face.size(); ++i) {
        const std::uint32_t f = s_.quad_face[cc.map.face[i]];
        out.face[f] = face++;
        out.rotation[f] = cc.map.rotation[i] & 3u;
      }
    for (const CodedRegion& c : regions_)
      for (std::uint32_t i = 0; i < c.face.size(); ++i) {
        out.face[c.face[i]] = face++;
        out.rotation[c.face[i]] = c.start[i] - faces_.offsets[c.face[i]];
      }
    if (face != nf || std::count(out.vertex.begin(), out.vertex.end(), kInvalid) != 0)
      internal("the output does not cover every input vertex and face");
  }

  const QuadSubmesh& s_;
  CanonicalMesh& cm_;
  RegionFaces faces_;
  PositionBits bits_;
  GlueGroups glue_;
  Numbering num_;
  RegionCoder coder_;
  std::uint32_t vertex_count_ = 0;
  std::uint32_t vq_ = 0, ids_ = 0;
  std::uint64_t work_ = 0, budget_ = 0;
  std::vector<std::uint32_t> comp_of_, loops_of_, interior_region_, free_local_, free_region_rank_;
  std::vector<std::vector<std::uint32_t>> touching_regions_, touching_glue_;
  std::vector<std::uint8_t> boundary_;
  std::vector<CodedRegion> free_, regions_;  // regions_: all, in the order assemble() put them
  std::vector<std::pair<bool, std::vector<std::uint32_t>>> tied_;
  std::vector<std::uint32_t> scratch_rank_, scratch_index_;  // per submesh vertex, for tie_key
  std::vector<std::uint32_t> step_base_, step_loops_;        // per place: first layout vertex, first loop
  std::vector<Choice> committed_, held_;
  std::vector<std::uint32_t> ref_original_, head_;  // per ref: input vertex, glue group's first ref
};

}  // namespace

bool operator==(const RegionCode& x, const RegionCode& y) {
  return std::tie(x.start, x.loop, x.position, x.degrees, x.corners, x.values, x.open) ==
         std::tie(y.start, y.loop, y.position, y.degrees, y.corners, y.values, y.open);
}

bool operator==(const RegionCodes& x, const RegionCodes& y) {
  return std::tie(x.layout_vertices, x.interior_vertices, x.regions, x.glue_offsets, x.glue) ==
         std::tie(y.layout_vertices, y.interior_vertices, y.regions, y.glue_offsets, y.glue);
}

CanonicalRegions canonical_regions(std::span<const std::uint32_t> face_offsets,
                                   std::span<const std::uint32_t> corners, std::uint32_t vertex_count,
                                   std::span<const float> positions, const QuadSubmesh& submesh,
                                   CanonicalMesh quads) {
  if (face_offsets.empty() || face_offsets.back() != corners.size() ||
      submesh.corner_vertex.size() != corners.size() ||
      (!positions.empty() && positions.size() != 3 * std::size_t{vertex_count}))
    internal("the polygon arrays are not the ones the quad submesh was cut from");
  for (std::uint32_t v : submesh.vertex_original)
    if (v >= vertex_count) internal("a submesh vertex copies no input vertex");
  return Canonicalizer(face_offsets, positions, vertex_count, submesh, quads).run();
}

}  // namespace qsp
