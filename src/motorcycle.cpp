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
  // `reached` maps a vertex to the arrival that reached it first, numbered over all steps from 1
  // (extraordinary vertices: 0); arrivals numbered from this step's `base` came at this step. So a
  // step finds its groups of particles arriving together without sorting them by vertex (the sort
  // cost 0.64M of mh_base's main-thread instructions). Only the set of traced edges matters: their
  // order in `traced` follows the particles'.
  std::vector<std::uint32_t> arrived;  // per particle: 0, or if first at its vertex, how many came
  std::vector<std::uint32_t> second;   // per particle first at its vertex: the next one to come
  std::vector<std::uint32_t> moving;
  std::uint32_t base = 1;
  for (std::uint32_t step = 1; !particles.empty(); ++step) {
    g.steps = step;
    const auto n = static_cast<std::uint32_t>(particles.size());
    arrived.assign(n, 0);
    second.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t h = particles[i];
      if (traced_edges.insert(std::min(h, adj.twin[h]), 0)) g.traced.push_back(h);
      const auto [first, fresh] = reached.try_insert(adj.dest(h), base + i);
      if (fresh) {
        arrived[i] = 1;
      } else if (first >= base && ++arrived[first - base] == 2) {
        second[first - base] = h;
      }
    }
    moving.clear();
    // Every group is judged against the state before this step: its vertex was new to `reached`.
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t h1 = particles[i], k = arrived[i];
      if (k == 0 || adj.boundary[adj.dest(h1)]) continue;
      if (k == 1) {
        moving.push_back(straight(h1));
      } else if (k == 2) {
        const std::uint32_t h2 = second[i];
        if (straight(h1) == adj.twin[h2]) {
          // head-on at a vertex: both stop
        } else if (adj.next(h1) == adj.twin[h2]) {
          moving.push_back(straight(h1));  // h1 runs along the face between the tracks: right-hand rule
        } else if (adj.next(h2) == adj.twin[h1]) {
          moving.push_back(straight(h2));
        } else {
          throw Error(ErrorCode::kInternal, "motorcycle: two particles meet at vertex " +
                                                std::to_string(adj.dest(h1)) +
                                                " neither head-on nor at a right angle");
        }
      }
      // three or four arriving together: all stop
    }
    base += n;
    particles.swap(moving);
  }
  return g;
}

}  // namespace qsp
