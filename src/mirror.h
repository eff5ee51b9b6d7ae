// src/mirror.h (internal): a quad mesh's mirror symmetry, an orientation-reversing automorphism of its
// faces, for predicting a vertex from its mirror image (format 3.17, the symmetry section). Characters,
// props and cages are mostly modelled with a mirror: every MakeHuman mesh, Spot, the fedora.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/mesh.h"
#include "stencil.h"

namespace qsp {

// One component's mirror: face `face` goes to face `image`, its corner c to the image's corner
// (turn - c) mod 4; the rest of the component follows across its edges. Positions reflect along
// `axis` (0 x, 1 y, 2 z).
struct MirrorSeed {
  std::uint32_t face = 0, image = 0, turn = 0, axis = 0;
};

struct MirrorMap {
  std::vector<std::uint32_t> image;  // per vertex: its mirror image, kInvalid where no seed reaches
  std::vector<std::uint8_t> axis;    // per vertex: its seed's axis (3 where none)
};

// The map the seeds determine. Propagated across edges: a face's image is the face across the image of the
// edge it is reached by. Throws Error(kFormat) "`what`: ..." if a seed is out of range or the seeds determine
// no orientation-reversing automorphism (a vertex or face with two images, a face with two preimages, an edge
// inside mapped to a boundary edge or back). O(faces). Safe on untrusted seeds.
MirrorMap mirror_vertices(std::span<const std::uint32_t> quads, const Adjacency& adj,
                          std::span<const MirrorSeed> seeds, const std::string& what);

// The mirror a symmetry section's `payload` (at byte `offset` in the file) determines on `quads`:
// decode_symmetry, then mirror_vertices, refused as they refuse it (Error(kFormat) naming the section's
// offset). Safe on untrusted input.
MirrorMap section_mirror(std::string_view payload, std::uint64_t offset, std::span<const std::uint32_t> quads,
                         const Adjacency& adj);

// The encoder's search: per component and axis, a mirror whose images lie near the vertices reflected
// in the plane across the component's middle: the component's first face against the faces whose
// centres lie nearest its reflected centre, in the four turns, nearest corners first, until one is an
// automorphism; the nearest of the three axes is kept where its rms distance is within 2% of the
// component's size. Seeds in component order. Deterministic in the quads and positions, so a renumbered mesh,
// canonicalized, finds the same. `found`, if given: mirror_vertices of the seeds, kept from the search's
// own propagations rather than made again.
std::vector<MirrorSeed> find_mirror(std::span<const std::uint32_t> quads, const Adjacency& adj,
                                    std::span<const float> positions, MirrorMap* found = nullptr);

// Sets each stencil's mirror source: the coding position of its vertex's image, where that comes first,
// and the axis. `coding`: the layout vertex at each coding position (empty: the identity).
void set_mirror_sources(std::vector<Stencil>& stencil, const std::vector<std::uint32_t>& coding,
                        const MirrorMap& mirror);

// The symmetry section's payload (format-spec/qsp_format.md, "Symmetry section"): the seed count, then
// per seed its face and image (varints) and a byte of its turn (bits 0-1) and axis (bits 2-3).
std::string encode_symmetry(std::span<const MirrorSeed> seeds);

// Its inverse for a mesh of `face_count` faces; every field checked against the bytes left and the
// counts before anything is allocated (Error(kFormat) with the byte offset). Safe on untrusted input.
std::vector<MirrorSeed> decode_symmetry(std::string_view payload, std::uint64_t base_offset,
                                        std::uint32_t face_count);

}  // namespace qsp
