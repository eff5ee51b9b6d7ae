// The motorcycle graph of §5: particles in lockstep, in time proportional to the traced edges.
#include <algorithm>
#include <string>
#include <utility>

#include "qsp/error.h"
#include "qsp/partition.h"
#include "u32map.h"

namespace qsp {

using detail::U32Map;

MotorcycleGraph trace_motorcycles(const Adjacency& adj, std::span<const std::uint32_t> extraordinary) {
  MotorcycleGraph g;
  auto is_boundary_edge = [&](std::uint32_t h) { return adj.is_exterior(h) || adj.is_exterior(adj.twin[h]); };
  // The edge straight ahead of half-edge h at its (ordinary, interior, valence-4) destination.
  auto straight = [&](std::uint32_t h) { return adj.next(adj.twin[adj.next(h)]); };

  std::vector<std::uint32_t> particles;  // each: the half-edge it is moving along this step
  U32Map reached(extraordinary.size() * 8);
  for (std::uint32_t v : extraordinary) {
    reached.insert(v, 0);
    const std::uint32_t h0 = adj.vertex_halfedge[v];
    std::uint32_t h = h0;
    do {
      // Boundary edges are in the graph anyway and a particle on one stops at its end: skip them.
      if (!is_boundary_edge(h)) particles.push_back(h);
      h = adj.rotate(h);
    } while (h != h0);
  }
  g.particles = static_cast<std::uint32_t>(particles.size());

  U32Map traced_edges(particles.size() * 4);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> arrivals;  // (vertex, half-edge)
  std::vector<std::uint32_t> moving;
  for (std::uint32_t step = 1; !particles.empty(); ++step) {
    g.steps = step;
    arrivals.clear();
    for (std::uint32_t h : particles) {
      if (traced_edges.insert(std::min(h, adj.twin[h]), 0)) g.traced.push_back(h);
      arrivals.emplace_back(adj.dest(h), h);
    }
    std::sort(arrivals.begin(), arrivals.end());
    moving.clear();
    // Every group is judged against the state before this step: a vertex first reached now is
    // inserted with this step's number, and no other group arrives at the same vertex.
    for (std::size_t i = 0; i < arrivals.size();) {
      std::size_t j = i;
      while (j < arrivals.size() && arrivals[j].first == arrivals[i].first) ++j;
      const std::uint32_t v = arrivals[i].first;
      const std::size_t k = j - i;
      const bool fresh = reached.insert(v, step);
      if (fresh && !adj.boundary[v]) {
        if (k == 1) {
          moving.push_back(straight(arrivals[i].second));
        } else if (k == 2) {
          const std::uint32_t h1 = arrivals[i].second, h2 = arrivals[i + 1].second;
          if (straight(h1) == adj.twin[h2]) {
            // head-on at a vertex: both stop
          } else if (adj.next(h1) == adj.twin[h2]) {
            moving.push_back(straight(h1));  // h1 runs along the face between the tracks: right-hand rule
          } else if (adj.next(h2) == adj.twin[h1]) {
            moving.push_back(straight(h2));
          } else {
            throw Error(ErrorCode::kInternal, "motorcycle: two particles meet at vertex " +
                                                  std::to_string(v) +
                                                  " neither head-on nor at a right angle");
          }
        }
        // three or four arriving together: all stop
      }
      i = j;
    }
    particles.swap(moving);
  }
  return g;
}

}  // namespace qsp
