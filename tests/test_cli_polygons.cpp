// qsp compress and decompress on polygon meshes (format 3.1): triangles, n-gons, non-manifold and
// mis-oriented pieces round-trip through the command line, compared by the test's own parse of both
// files; what is not a mesh keeps its message; --keep-order gives back the file's own order.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/codec.h"
#include "support/cli.h"
#include "support/files.h"
#include "support/mesh_text.h"
#include "support/minor.h"

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
  EXPECT_EQ(qsp[9], testing::minor_of_file_with(qsp, 1)) << "a polygon mesh's file is format 3.1";
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
  // Extra data is kept, as for quad meshes (vertex weights, a line kept as text), and dropped on request.
  std::string weighted;  // every vertex with a weight: v x y z w
  for (std::size_t at = 0, end = 0; (end = std::string_view(kPolygonObj).find('\n', at)) != std::string::npos;
       at = end + 1) {
    const std::string line(kPolygonObj + at, end - at);
    weighted += line + (line.starts_with("v ") ? " 1\n" : "\n");
  }
  testing::spit(p("weights.obj"), weighted + "vp 0.5\n");
  const auto u = run_qsp("compress -q " + quote(p("weights.obj")));
  EXPECT_EQ(u.exit_code, 0) << u.err;
  const PolygonMesh weights = decode_polygons(testing::slurp(p("weights.obj.qsp")));
  ASSERT_EQ(weights.vertex_properties.size(), 1u);
  EXPECT_EQ(weights.vertex_properties[0].values, std::vector<double>(weights.vertex_count(), 1.0));
  EXPECT_EQ(run_qsp("compress -f -q --drop extra " + quote(p("weights.obj"))).exit_code, 0);
  EXPECT_TRUE(decode_polygons(testing::slurp(p("weights.obj.qsp"))).vertex_properties.empty());
  testing::spit(p("prose.obj"), std::string(kPolygonObj) + "vp 0.5\n");
  ASSERT_EQ(run_qsp("compress -q " + quote(p("prose.obj"))).exit_code, 0);
  EXPECT_EQ(decode_polygons(testing::slurp(p("prose.obj.qsp"))).kept_lines,
            std::vector<std::string>{"vp 0.5"});
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

// The comment lines ('#') of a text mesh, in order.
std::vector<std::string> comment_lines(const std::string& text) {
  std::vector<std::string> out;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    if (text[at] == '#') out.push_back(text.substr(at, end - at));
    at = end + 1;
  }
  return out;
}

// A polygon mesh file keeps what a quad mesh file keeps through reorder: its leading comment block, not a
// comment after it.
TEST_F(CliPolygons, ReorderKeepsTheLeadingCommentsAsForQuads) {
  const std::string head =
      "# licence\n# second line\nOFF\n5 2 0\n# later\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n";
  testing::spit(p("poly.off"), head + "4 0 1 2 3\n3 1 4 2\n");
  testing::spit(p("quads.off"),
                "# licence\n# second line\nOFF\n4 1 0\n# later\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  std::vector<std::vector<std::string>> kept;
  for (const char* name : {"quads", "poly"}) {
    const std::string in = p(std::string(name) + ".off"), out = p(std::string(name) + ".out.obj");
    const auto r = run_qsp("reorder --like " + quote(in) + " " + quote(in) + " -o " + quote(out));
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    kept.push_back(comment_lines(testing::slurp(out)));
  }
  EXPECT_EQ(kept[0], (std::vector<std::string>{"# licence", "# second line"}));
  EXPECT_EQ(kept[1], kept[0]);
  const auto r = run_qsp("reorder --drop comment --like " + quote(p("poly.off")) + " " +
                         quote(p("poly.off")) + " -o " + quote(p("none.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(comment_lines(testing::slurp(p("none.obj"))).empty());
}

// The note naming the data dropped is said once OUT is written, so never for an OUT that could not be.
TEST_F(CliPolygons, TheDroppedNoteFollowsTheOutput) {
  testing::spit(p("m.obj"), kPolygonObj);
  testing::spit(p("uv.obj"), std::string(kPolygonObj) + "vt 0 0\n");
  const std::string call = "reorder --drop uv --like " + quote(p("m.obj")) + " " + quote(p("uv.obj")) +
                           " -o " + quote(p("out.obj"));
  auto r = run_qsp(call);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::size_t at = r.err.find("dropped");
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("dropped", at + 1), std::string::npos) << "said twice: " << r.err;
  r = run_qsp(call);  // OUT exists now
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("already exists"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("dropped"), std::string::npos) << r.err;
}

// Coordinates are read as the quad reader reads them: one that does not round to a finite float32 is
// refused by every subcommand, with the quad mesh's exit code; more digits than float32 keeps is refused
// by reorder unless --float32.
TEST_F(CliPolygons, CoordinatesAreTakenAsForQuads) {
  const std::string huge = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 1e39\nv 2 0 0\nf 1 2 3 4\n";
  testing::spit(p("quad.obj"), huge);
  testing::spit(p("poly.obj"), huge + "f 2 5 3\n");
  testing::spit(p("ok.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  for (const std::string& call :
       {std::string("fingerprint "), std::string("stats "), "match " + quote(p("ok.obj")) + " "}) {
    const auto q = run_qsp(call + quote(p("quad.obj")));
    const auto r = run_qsp(call + quote(p("poly.obj")));
    EXPECT_NE(q.exit_code, 0) << call << q.out;
    EXPECT_EQ(r.exit_code, q.exit_code) << call << r.out;
    EXPECT_NE(r.err.find("outside the float32 range"), std::string::npos) << call << r.err;
  }
  testing::spit(p("digits.obj"),
                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0.1000000001\nv 2 0 0\nf 1 2 3 4\nf 2 5 3\n");
  const std::string call = "reorder --like " + quote(p("digits.obj")) + " " + quote(p("digits.obj")) + " -o ";
  // reorder keeps the float64 (as compress does), or rounds it with --float32.
  auto r = run_qsp(call + quote(p("a.obj")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(testing::slurp(p("a.obj")).find("v 0 1 0.1000000001\n"), std::string::npos)
      << testing::slurp(p("a.obj"));
  r = run_qsp(call + quote(p("b.obj")) + " --float32");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("rounded 1 coordinate to float32"), std::string::npos) << r.err;
  // layout warns, naming the coordinate as it does for a quad mesh.
  r = run_qsp("layout " + quote(p("digits.obj")) + " -o " + quote(p("layout.obj")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + p("digits.obj") + ": vertex 3 has 0.1000000001"), std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace qsp
