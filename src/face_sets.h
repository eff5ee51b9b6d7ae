// src/face_sets.h (internal): faces joined across chosen edges, labelled by union-find.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace qsp::detail {

// Labels the face sets connected by the pairs that `pairs(join)` passes to join(f, g), numbering sets
// by their first face (so in any order of the pairs); `first_face` receives each set's smallest face.
template <class Pairs>
std::vector<std::uint32_t> label_joined_faces(std::uint32_t nf, Pairs pairs,
                                              std::vector<std::uint32_t>& first_face) {
  std::vector<std::uint32_t> parent(nf);
  for (std::uint32_t f = 0; f < nf; ++f) parent[f] = f;
  auto find = [&](std::uint32_t f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  pairs([&](std::uint32_t f, std::uint32_t g) {
    const std::uint32_t a = find(f), b = find(g);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);  // a root is its set's smallest face
  });
  std::vector<std::uint32_t> label(nf);
  first_face.clear();
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::uint32_t r = find(f);
    if (r == f) {
      label[f] = static_cast<std::uint32_t>(first_face.size());
      first_face.push_back(f);
    } else {
      label[f] = label[r];  // r < f: already labelled
    }
  }
  return label;
}

// The face sets connected through the interior half-edges h (< 4*nf) for which joins(h) is true.
// Scans the twins in order: a flood fill would chase them at random, which dominates on large meshes.
template <class Joins>
std::vector<std::uint32_t> label_face_sets(std::uint32_t nf, const std::vector<std::uint32_t>& twin,
                                           Joins joins, std::vector<std::uint32_t>& first_face) {
  const std::uint32_t nh = 4 * nf;
  return label_joined_faces(
      nf,
      [&](auto join) {
        for (std::uint32_t h = 0; h < nh; ++h) {
          const std::uint32_t t = twin[h];
          if (t > h && t < nh && joins(h)) join(h >> 2, t >> 2);
        }
      },
      first_face);
}

}  // namespace qsp::detail
