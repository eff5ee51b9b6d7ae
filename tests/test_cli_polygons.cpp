// qsp compress and decompress on polygon meshes (format 3.1): triangles, n-gons, non-manifold and
// mis-oriented pieces round-trip through the command line, compared by the test's own parse of both
// files; what is not a mesh keeps its message; --keep-order gives back the file's own order.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "support/cli.h"
#include "support/files.h"
#include "support/mesh_text.h"

namespace qsp {
namespace {

using testing::quote;
using testing::run_qsp;

// A 3x2 grid of quads with one cell split into two triangles, a pentagon on its top edge and a fin quad
// on one inner edge (three faces on an edge): non-quad and non-manifold at once.
const char* kPolygonObj =
    "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\n"
    "v 0 1 0\nv 1 1 0\nv 2 1 0\nv 3 1 0\n"
    "v 0 2 0\nv 1 2 0\nv 2 2 0\nv 3 2 0\n"
    "v 1.5 3 0.5\nv 1 1 1\nv 2 1 1\n"
    "f 1 2 6 5\nf 2 3 7 6\nf 3 4 8\nf 3 8 7\n"
    "f 5 6 10 9\nf 6 7 11 10\nf 7 8 12 11\n"
    "f 9 10 11 12 13\n"
    "f 6 7 15 14\n";

// Each face as the cyclic sequence of its corners' coordinate texts, rotated to start at the smallest,
// sorted: the faces up to vertex renumbering (the positions here are distinct).
std::vector<std::vector<std::string>> faces_of(const testing::TextMesh& m) {
  std::vector<std::vector<std::string>> out;
  for (const auto& f : m.faces) {
    std::vector<std::string> face;
    for (long v : f) {
      std::string key;
      for (std::size_t k = 0; k < 3; ++k) key += m.vertices.at(static_cast<std::size_t>(v)).at(k) + " ";
      face.push_back(key);
    }
    std::rotate(face.begin(), std::min_element(face.begin(), face.end()), face.end());
    out.push_back(face);
  }
  std::sort(out.begin(), out.end());
  return out;
}

class CliPolygons : public testing::TempDirTest {};

TEST_F(CliPolygons, CompressDecompressKeepsEveryFace) {
  testing::spit(p("m.obj"), kPolygonObj);
  const auto c = run_qsp("compress " + quote(p("m.obj")));
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const std::string qsp = testing::slurp(p("m.obj.qsp"));
  ASSERT_GT(qsp.size(), 11u);
  EXPECT_EQ(qsp[9], 1) << "a polygon mesh's file is format 3.1";
  for (const char* ext : {"obj", "off"}) {
    const std::string out = p(std::string("back.") + ext);
    const auto d = run_qsp("decompress " + quote(p("m.obj.qsp")) + " -o " + quote(out));
    ASSERT_EQ(d.exit_code, 0) << d.err;
    const testing::TextMesh in = testing::parse_obj_text(kPolygonObj);
    const testing::TextMesh back = std::string(ext) == "obj" ? testing::parse_obj_text(testing::slurp(out))
                                                             : testing::parse_off_text(testing::slurp(out));
    EXPECT_EQ(back.vertices.size(), in.vertices.size()) << ext;
    EXPECT_EQ(faces_of(back), faces_of(in)) << ext;
  }
  // Canonical: the decompressed text compresses to the same bytes.
  const auto again = run_qsp("compress " + quote(p("back.obj")));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(testing::slurp(p("back.obj.qsp")), qsp);
}

TEST_F(CliPolygons, StandardStreamsAndQuantizedPositions) {
  testing::spit(p("m.obj"), kPolygonObj);
  const auto c = run_qsp("compress --quantize 12 - -c < " + quote(p("m.obj")));
  ASSERT_EQ(c.exit_code, 0) << c.err;
  testing::spit(p("m.qsp"), c.out);
  const auto d = run_qsp("decompress -c " + quote(p("m.qsp")));
  ASSERT_EQ(d.exit_code, 0) << d.err;
  const testing::TextMesh back = testing::parse_obj_text(d.out);
  EXPECT_EQ(back.vertices.size(), 15u);
  EXPECT_EQ(back.faces.size(), 9u);
  std::vector<std::size_t> degrees;
  for (const auto& f : back.faces) degrees.push_back(f.size());
  std::sort(degrees.begin(), degrees.end());
  EXPECT_EQ(degrees, (std::vector<std::size_t>{3, 3, 4, 4, 4, 4, 4, 4, 5}));
}

TEST_F(CliPolygons, KeepOrderGivesBackTheFileOrder) {
  testing::spit(p("m.obj"), kPolygonObj);
  const auto c = run_qsp("compress --keep-order " + quote(p("m.obj")));
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const auto d = run_qsp("decompress -c " + quote(p("m.obj.qsp")));
  ASSERT_EQ(d.exit_code, 0) << d.err;
  const testing::TextMesh in = testing::parse_obj_text(kPolygonObj), back = testing::parse_obj_text(d.out);
  EXPECT_EQ(back.faces, in.faces);
  EXPECT_EQ(back.vertices, in.vertices);
}

TEST_F(CliPolygons, WhatIsNotAMeshKeepsItsMessage) {
  // An index out of range and a face repeating a vertex, in files that also have triangles.
  testing::spit(p("range.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\nf 1 2 9\n");
  const auto r = run_qsp("compress " + quote(p("range.obj")));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("range.obj:5: vertex index 9 is out of range"), std::string::npos) << r.err;
  testing::spit(p("repeat.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 2 2 4\n");
  const auto d = run_qsp("compress " + quote(p("repeat.obj")));
  EXPECT_NE(d.exit_code, 0);
  EXPECT_NE(d.err.find("repeat.obj:6:"), std::string::npos) << d.err;
  EXPECT_NE(d.err.find("repeats vertex"), std::string::npos) << d.err;
  // Other data than positions is refused unless dropped, as for quad meshes.
  testing::spit(p("uv.obj"), std::string(kPolygonObj) + "vt 0 0\n");
  const auto u = run_qsp("compress " + quote(p("uv.obj")));
  EXPECT_NE(u.exit_code, 0);
  EXPECT_NE(u.err.find("--drop uv"), std::string::npos) << u.err;
  EXPECT_EQ(run_qsp("compress -q --drop uv " + quote(p("uv.obj"))).exit_code, 0);
}

// A polygon .qsp is the mesh it was compressed from for every subcommand that reads polygon meshes:
// the same fingerprint, isomorphic to it, the same counts.
TEST_F(CliPolygons, APolygonQspIsItsMeshForMatchFingerprintStats) {
  testing::spit(p("m.obj"), kPolygonObj);
  ASSERT_EQ(run_qsp("compress " + quote(p("m.obj"))).exit_code, 0);
  const auto m = run_qsp("match " + quote(p("m.obj.qsp")) + " " + quote(p("m.obj")));
  EXPECT_EQ(m.exit_code, 0) << m.err;
  const auto f = run_qsp("fingerprint " + quote(p("m.obj.qsp")) + " " + quote(p("m.obj")));
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_EQ(f.out.substr(0, 16), f.out.substr(f.out.find('\n') + 1, 16)) << f.out;
  const auto s = run_qsp("stats " + quote(p("m.obj")));
  EXPECT_EQ(s.exit_code, 0) << s.err;
  const std::size_t at = s.out.find("polygons: ");
  ASSERT_NE(at, std::string::npos) << s.out;
  const auto q = run_qsp("stats " + quote(p("m.obj.qsp")));
  EXPECT_EQ(q.exit_code, 0) << q.err;
  EXPECT_NE(q.out.find(s.out.substr(at, s.out.find('\n', at) - at)), std::string::npos) << q.out;
}

}  // namespace
}  // namespace qsp
