// src/mesh_split.h (internal): the seam of build_adjacency's two-thread path, declared for tests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "qsp/mesh.h"

namespace qsp::detail {

// build_adjacency uses two threads from this many faces (and when asked to). Below, starting a thread
// and meeting at its four barriers costs about what halving the work saves.
inline constexpr std::size_t kAdjacencyTwoThreadsFrom = 4096;

// The adjacency of `quads` over `vertex_count` vertices built on two threads: the faces' checks and
// bucket counts split by faces, the twin matching by vertices, valences beside components. Equal,
// member for member, to the one-thread result; std::nullopt when the mesh is invalid in any way (or
// no thread is to be had), for the one-thread path to name the problem as it always does. Expects the
// sizes build_adjacency checked first.
std::optional<Adjacency> build_adjacency_two_threads(std::span<const std::uint32_t> quads,
                                                     std::uint32_t vertex_count);

}  // namespace qsp::detail
