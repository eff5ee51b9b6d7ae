// OpenMesh's reading of a mesh file, an independent reader to cross-check qsp's own (tests only).
#pragma once

#include <gtest/gtest.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <cstdint>
#include <filesystem>

#include "qsp/mesh.h"

namespace qsp::testing {

// The file as OpenMesh reads it (OBJ, OFF, PLY), as a QuadMesh: its add_face keeps corner order and
// gives the face the halfedge from the last corner to the first, so faces keep their first corner.
// Adds a test failure if OpenMesh cannot read it. Only for valid manifold meshes: OpenMesh silently
// duplicates vertices of non-manifold faces.
inline QuadMesh read_with_openmesh(const std::filesystem::path& p) {
  OpenMesh::PolyMesh_ArrayKernelT<> om;
  OpenMesh::IO::Options options;
  EXPECT_TRUE(OpenMesh::IO::read_mesh(om, p.string(), options)) << p;
  QuadMesh m;
  for (const auto vh : om.vertices()) {
    const auto& pt = om.point(vh);
    m.positions.insert(m.positions.end(), {pt[0], pt[1], pt[2]});
  }
  for (const auto fh : om.faces()) {
    const auto h0 = om.halfedge_handle(fh);
    auto h = h0;
    do {
      m.quads.push_back(static_cast<std::uint32_t>(om.to_vertex_handle(h).idx()));
      h = om.next_halfedge_handle(h);
    } while (h != h0);
  }
  return m;
}

}  // namespace qsp::testing
