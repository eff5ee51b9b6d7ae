// qsp/canonical.h: canonical labelling and traversal of schematic partitions (§6).
// Two meshes get equal codes exactly when they are isomorphic with orientation.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "qsp/mesh.h"
#include "qsp/partition.h"

namespace qsp {

// The connectivity of one component as a canonical traversal from its canonical root dart.
// Darts are labelled in discovery order, edges in pairs (2e, 2e+1 = twins, so twins cost nothing);
// darts are visited in label order and each says where its `next` goes. Decodable on its own.
struct TopologyCode {
  ComponentKind kind = ComponentKind::kUnstructured;
  std::uint32_t a = 0, b = 0, twist = 0;  // kAnnulus / kTorus sizes (see ComponentPartition)
  // Per dart in label order: 0 = next is a new edge (labelled now: next gets 2E, its twin 2E+1),
  // k > 0 = next is the k-th (1-based, by label) dart that has no predecessor yet.
  std::vector<std::uint32_t> next_ref;
  std::vector<std::uint32_t> edge_length;  // per edge in label order
  std::vector<std::uint8_t> corner;        // per dart in label order: origin is a corner of its face
};

bool operator==(const TopologyCode& x, const TopologyCode& y);
// Strict weak order used to sort components canonically (kind, sizes, then the streams).
bool operator<(const TopologyCode& x, const TopologyCode& y);

struct CanonicalComponent {
  TopologyCode code;
  ComponentPartition part;          // relabelled in canonical order; still linked to the input mesh
  LayoutMap map;                    // grid_layout(part) vertex/face -> input mesh vertex/face
  std::uint32_t automorphisms = 1;  // orientation-preserving self-isomorphisms found (root ties)
};

struct CanonicalMesh {
  std::vector<CanonicalComponent> components;  // in canonical order
  std::vector<std::uint32_t> unreferenced;     // input vertices in no face, by position (float bits)
};

// Canonical form of a partitioned mesh. Components are ordered by code, equal codes by positions;
// within a component, roots that tie on topology are chosen between by positions (lexicographic on
// the float bits in layout order), so the result depends only on the mesh up to isomorphism plus
// its positions. Never compares all flags pairwise: dart colours are refined first. `threads`: 1 =
// this thread only; 0 = a second thread for the components when there are several and enough work
// besides the largest, else for a large component's patch walks; 2 or more = two threads whenever there are
// two components (tests). The result never depends on it; errors are those the first failing component gives,
// as on one thread.
CanonicalMesh canonicalize(const QuadMesh& mesh, const Adjacency& adj, const Partition& partition,
                           unsigned threads = 0);

// The starts of a canonical traversal that all give `comp.code`: one per orientation-preserving
// automorphism of the component, so their number is its topological symmetry count. General
// components: darts of comp.part.schematic (0, the canonical root, among them); annulus/torus: anchor
// half-edges of the mesh. (comp.automorphisms counts, for tori and annuli, only the anchors whose
// positions tie.) `adj` is the adjacency comp was built from. Cost: a few schematic traversals, or
// O(component faces) for a torus. Never throws but for memory when `comp` is what canonicalize made on
// `adj`; checks neither, so another pair may read out of range: not for untrusted input.
std::vector<std::uint32_t> canonical_starts(const Adjacency& adj, const CanonicalComponent& comp);

// comp.part with its traversal started at `start` (one of canonical_starts): same code, same layout,
// linked to the mesh through another automorphism. layout_to_mesh(result, adj) gives its LayoutMap.
// Never throws but for memory when `start` is one of those; checks nothing (another start may give
// another code, and an index out of range is read out of range): not for untrusted input.
ComponentPartition canonical_from_start(const Adjacency& adj, const CanonicalComponent& comp,
                                        std::uint32_t start);

// Rebuilds the component a code describes, in canonical numbering (not linked to any mesh).
// Throws Error(kFormat) if the code is not a valid schematic partition. Safe on untrusted input.
ComponentPartition partition_from_code(const TopologyCode& code);

// 64-bit hash of the canonical codes of all components (in canonical order) and the number of
// unreferenced vertices: equal for isomorphic meshes; different ones collide with probability ~2^-64.
// The integers are hashed in the machine's byte order. Never throws; reads only the codes, so it is safe
// on any CanonicalMesh, one decoded from an untrusted file too. O(size of the codes).
std::uint64_t topology_fingerprint(const CanonicalMesh& mesh);

}  // namespace qsp
