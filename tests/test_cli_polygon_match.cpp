// `qsp match` and `qsp fingerprint` on polygon meshes (issue 20), end to end: every non-quad or
// non-manifold shared mesh against a renumbered copy (vertices, faces, rotated corner lists) matches,
// with MAP and FACEMAP checked here face by face, and shares its fingerprint; a copy with one diagonal
// between two triangles flipped is "not isomorphic" (exit 1) with another fingerprint; options the
// polygon path cannot honour are refused, never answered wrongly.
#include <gtest/gtest.h>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <numeric>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli.h"
#include "support/corpus.h"
#include "support/polygon.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;
using testing::Grid;
using testing::Poly;
using testing::quote;
using testing::run_qsp;

using CliPolygonMatch = testing::TempDirTest;

std::string obj_text(const Poly& p) {
  std::string out;
  char buf[32];
  for (std::uint32_t v = 0; v < p.nv; ++v) {
    out += "v";
    for (int k = 0; k < 3; ++k) {
      const float x = p.positions.empty() ? static_cast<float>(k == 0 ? v : 0) : p.positions[3 * v + k];
      out += ' ';
      out.append(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
    }
    out += '\n';
  }
  for (std::uint32_t f = 0; f < p.face_count(); ++f) {
    out += "f";
    for (std::uint32_t c = p.offsets[f]; c < p.offsets[f + 1]; ++c) {
      out += ' ';
      out += std::to_string(p.corners[c] + 1);
    }
    out += '\n';
  }
  return out;
}

// A renumbered copy (positions follow their vertices).
Poly renumbered(const Poly& p, std::uint32_t seed) { return testing::shuffled(p, seed); }

// MAP and FACEMAP as match writes them, checked against both meshes' faces: a bijection of vertices,
// every face of A a face of B of its degree with the same cyclic corner order, each face of B once.
void expect_maps_face_by_face(const Poly& a, const Poly& b, const std::string& map,
                              const std::string& faces) {
  std::istringstream vm(map), fm(faces);
  std::vector<std::uint32_t> vertex(a.nv);
  for (auto& v : vertex) ASSERT_TRUE(vm >> v);
  std::string rest;
  EXPECT_FALSE(vm >> rest) << "MAP has more lines than A has vertices";
  std::set<std::uint32_t> images(vertex.begin(), vertex.end());
  ASSERT_EQ(images.size(), a.nv);
  ASSERT_TRUE(images.empty() || *images.rbegin() < b.nv);
  std::vector<int> used(b.face_count(), 0);
  for (std::uint32_t f = 0; f < a.face_count(); ++f) {
    std::uint32_t g = 0, rot = 0;
    ASSERT_TRUE(fm >> g >> rot) << "FACEMAP ends at face " << f;
    ASSERT_LT(g, b.face_count());
    ASSERT_EQ(used[g]++, 0);
    const std::uint32_t d = a.degree(f);
    ASSERT_EQ(b.degree(g), d);
    ASSERT_LT(rot, d);
    for (std::uint32_t c = 0; c < d; ++c)
      ASSERT_EQ(vertex[a.corners[a.offsets[f] + c]], b.corners[b.offsets[g] + (c + rot) % d])
          << "face " << f << " corner " << c;
  }
}

// The 16 hex digits fingerprint prints for one file.
std::string fingerprint(const std::string& path) {
  const auto r = run_qsp("fingerprint " + quote(path));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.out.substr(0, 16);
}

bool is_polygon_mesh(const Poly& p) {
  for (std::uint32_t f = 0; f < p.face_count(); ++f)
    if (p.degree(f) != 4) return true;
  return false;
}

TEST_F(CliPolygonMatch, SharedPolygonMeshesMatchRenumberedCopiesAndNotFlippedDiagonals) {
  QSP_NEEDS_SHARED();
  int matched = 0, flipped = 0;
  for (const fs::path& path : testing::shared_meshes()) {
    const Poly a = testing::read_faces(path);
    if (!is_polygon_mesh(a) && testing::expected_valid(path)) continue;  // the quad path's own tests
    SCOPED_TRACE(path.string());
    const std::string fa = p("a.obj"), fb = p("b.obj"), fc = p("c.obj");
    testing::spit(fa, obj_text(a));
    const Poly b = renumbered(a, 5);
    testing::spit(fb, obj_text(b));
    fs::remove(p("map.txt"));
    fs::remove(p("faces.txt"));
    const auto r = run_qsp("match " + quote(fa) + " " + quote(fb) + " -o " + quote(p("map.txt")) +
                           " --faces " + quote(p("faces.txt")));
    if (r.exit_code == 2 && r.err.find("repeats vertex") != std::string::npos) continue;  // not a mesh
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_EQ(r.out.rfind("isomorphic: polygon meshes; ", 0), 0u) << r.out;
    expect_maps_face_by_face(a, b, testing::slurp(p("map.txt")), testing::slurp(p("faces.txt")));
    EXPECT_EQ(fingerprint(fa), fingerprint(fb));
    ++matched;
    Poly c;
    if (!flip_a_diagonal(a, c)) continue;
    testing::spit(fc, obj_text(renumbered(c, 6)));
    const auto n = run_qsp("match " + quote(fa) + " " + quote(fc));
    EXPECT_EQ(n.exit_code, 1) << n.out << n.err;
    EXPECT_EQ(n.out.rfind("not isomorphic: ", 0), 0u) << n.out;
    EXPECT_NE(fingerprint(fa), fingerprint(fc));
    ++flipped;
  }
  EXPECT_GE(matched, 20);
  EXPECT_GE(flipped, 8);
}

// A quad-dominant mesh as read from the corpus file itself (its own OBJ, all its statements) against
// a renumbered copy; the report says which isomorphism it is; a quad mesh and a polygon mesh compare
// by face degrees.
TEST_F(CliPolygonMatch, SuzanneAgainstItsCopyAndAgainstAQuadMesh) {
  QSP_NEEDS_SHARED();
  const std::string suzanne = (testing::shared_dir() / "meshes" / "pmp_suzanne.obj").string();
  const Poly a = testing::read_faces(suzanne);
  const Poly b = renumbered(a, 11);
  testing::spit(p("b.obj"), obj_text(b));
  auto r = run_qsp("match " + quote(suzanne) + " " + quote(p("b.obj")) + " --faces " + quote(p("faces.txt")) +
                   " -o " + quote(p("map.txt")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_maps_face_by_face(a, b, testing::slurp(p("map.txt")), testing::slurp(p("faces.txt")));
  r = run_qsp("match " + quote(suzanne) + " " + quote(std::string(QSP_TESTDATA_DIR) + "/cube_4.obj"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("not isomorphic: face degrees: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(suzanne + " has 32 triangles"), std::string::npos) << r.out;
}

// Hand cases: a triangle fan against the quad it fills; two meshes differing only by which cell of a
// grid is split into triangles; a bow tie (two quads at one vertex: non-manifold, read by the quad
// reader, then cut) against a renumbered copy.
TEST_F(CliPolygonMatch, HandCases) {
  testing::spit(p("quad.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 0\nf 1 2 3 4\n");
  testing::spit(p("fan.obj"),
                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 0\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n");
  auto r = run_qsp("match " + quote(p("quad.obj")) + " " + quote(p("fan.obj")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("not isomorphic: face degrees: " + p("quad.obj") + " has 0 triangles, " +
                       p("fan.obj") + " has 4 triangles"),
            std::string::npos)
      << r.out;
  EXPECT_NE(fingerprint(p("quad.obj")), fingerprint(p("fan.obj")));

  const Poly corner = Grid::make(3, 3, [](int i, int j) { return i == 0 && j == 0 ? 't' : 'q'; }).p;
  const Poly middle = Grid::make(3, 3, [](int i, int j) { return i == 1 && j == 1 ? 't' : 'q'; }).p;
  testing::spit(p("corner.obj"), obj_text(corner));
  testing::spit(p("middle.obj"), obj_text(middle));
  r = run_qsp("match " + quote(p("corner.obj")) + " " + quote(p("middle.obj")));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_EQ(r.out.find("face degrees"), std::string::npos) << r.out;  // the degrees agree
  EXPECT_NE(fingerprint(p("corner.obj")), fingerprint(p("middle.obj")));

  const std::string bowtie =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 1 0\nv 2 2 0\nv 1 2 0\nf 1 2 3 4\nf 3 5 6 7\n";
  const std::string copy =
      "v 1 1 0\nv 2 2 0\nv 0 0 0\nv 2 1 0\nv 1 0 0\nv 1 2 0\nv 0 1 0\nf 4 2 6 1\nf 1 7 3 5\n";
  testing::spit(p("bowtie.obj"), bowtie);
  testing::spit(p("bowtie2.obj"), copy);
  r = run_qsp("match " + quote(p("bowtie.obj")) + " " + quote(p("bowtie2.obj")) + " -o " + quote(p("bmap")) +
              " --faces " + quote(p("bfaces")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Two isomorphisms (the quads swap about the shared vertex): one of them, checked face by face.
  Poly pa, pb;
  pa.nv = pb.nv = 7;
  pa.face({0, 1, 2, 3});
  pa.face({2, 4, 5, 6});
  pb.face({3, 1, 5, 0});
  pb.face({0, 6, 2, 4});
  expect_maps_face_by_face(pa, pb, testing::slurp(p("bmap")), testing::slurp(p("bfaces")));
  EXPECT_EQ(fingerprint(p("bowtie.obj")), fingerprint(p("bowtie2.obj")));
  // The same file through standard input (read once) and as a quad-only input: the same answer.
  r = run_qsp("match - " + quote(p("bowtie2.obj")) + " < " + quote(p("bowtie.obj")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run_qsp("fingerprint - < " + quote(p("fan.obj")));
  EXPECT_EQ(r.out.substr(0, 16), fingerprint(p("fan.obj")));
}

// --prefer-order on a symmetric polygon mesh: the identity where it is an isomorphism; refused with a
// reason where it is not (never another map passed off as order-keeping). --allow-mirror as for quads.
TEST_F(CliPolygonMatch, OptionsAreHonouredOrRefused) {
  const Poly middle = Grid::make(3, 3, [](int i, int j) { return i == 1 && j == 1 ? 't' : 'q'; }).p;
  testing::spit(p("a.obj"), obj_text(middle));
  auto r = run_qsp("match --prefer-order " + quote(p("a.obj")) + " " + quote(p("a.obj")) + " -o -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string identity;
  for (std::uint32_t v = 0; v < middle.nv; ++v) {
    identity += std::to_string(v);
    identity += '\n';
  }
  EXPECT_EQ(r.out, identity);
  EXPECT_NE(r.err.find("the identity of indices"), std::string::npos) << r.err;
  testing::spit(p("b.obj"), obj_text(renumbered(middle, 3)));
  r = run_qsp("match --prefer-order " + quote(p("a.obj")) + " " + quote(p("b.obj")));
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find("--prefer-order"), std::string::npos) << r.err;

  // A chiral mesh (two split cells, off centre) and its mirror image.
  const Poly chiral =
      Grid::make(4, 3, [](int i, int j) { return (i == 0 && j == 0) || (i == 2 && j == 1) ? 't' : 'q'; }).p;
  Poly mirror = chiral;
  for (std::uint32_t f = 0; f < mirror.face_count(); ++f)
    std::reverse(mirror.corners.begin() + mirror.offsets[f] + 1,
                 mirror.corners.begin() + mirror.offsets[f + 1]);
  testing::spit(p("c.obj"), obj_text(chiral));
  testing::spit(p("m.obj"), obj_text(mirror));
  r = run_qsp("match " + quote(p("c.obj")) + " " + quote(p("m.obj")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("pass --allow-mirror"), std::string::npos) << r.out;
  r = run_qsp("match --allow-mirror " + quote(p("c.obj")) + " " + quote(p("m.obj")) + " -o " +
              quote(p("map")) + " --faces " + quote(p("faces")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("isomorphic (orientation-reversing"), std::string::npos) << r.out;
  // Corner c of A's face is corner (R - c) % d of B's.
  std::istringstream vm(testing::slurp(p("map"))), fm(testing::slurp(p("faces")));
  std::vector<std::uint32_t> vertex(chiral.nv);
  for (auto& v : vertex) vm >> v;
  for (std::uint32_t f = 0; f < chiral.face_count(); ++f) {
    std::uint32_t g = 0, rot = 0;
    ASSERT_TRUE(fm >> g >> rot);
    const std::uint32_t d = chiral.degree(f);
    ASSERT_EQ(mirror.degree(g), d);
    for (std::uint32_t c = 0; c < d; ++c)
      EXPECT_EQ(vertex[chiral.corners[chiral.offsets[f] + c]],
                mirror.corners[mirror.offsets[g] + (rot + d - c) % d]);
  }
}

// reorder --like on polygon meshes: OUT has REF's faces exactly (corner order too) and IN's positions;
// .qsp output keeps them; extra data not dropped and another topology are refused.
TEST_F(CliPolygonMatch, ReorderGivesTheReferencesFaces) {
  QSP_NEEDS_SHARED();
  const std::string suzanne = (testing::shared_dir() / "meshes" / "pmp_suzanne.obj").string();
  const Poly ref = testing::read_faces(suzanne);
  Poly in = renumbered(ref, 21);
  testing::spit(p("in.obj"), obj_text(in));
  auto r =
      run_qsp("reorder --like " + quote(suzanne) + " " + quote(p("in.obj")) + " -o " + quote(p("out.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Poly out = testing::read_faces(p("out.obj"));
  EXPECT_EQ(out.offsets, ref.offsets);
  EXPECT_EQ(out.corners, ref.corners);
  EXPECT_EQ(out.positions, ref.positions);  // the renumbering undone: every vertex where it was
  // Moved positions: Suzanne's eyes turn onto themselves, and the turn taken is the one keeping each
  // eye vertex nearest (relative to the centroids): OUT is REF moved, vertex for vertex.
  for (float& x : in.positions) x += 1.0f;
  testing::spit(p("in.obj"), obj_text(in));
  r = run_qsp("reorder -f --like " + quote(suzanne) + " " + quote(p("in.obj")) + " -o " +
              quote(p("out.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  out = testing::read_faces(p("out.obj"));
  EXPECT_EQ(out.offsets, ref.offsets);
  EXPECT_EQ(out.corners, ref.corners);
  ASSERT_EQ(out.positions.size(), ref.positions.size());
  for (std::size_t i = 0; i < ref.positions.size(); ++i)
    EXPECT_EQ(out.positions[i], ref.positions[i] + 1.0f) << i;
  // Into a .qsp (format 3.1, the order kept): decompressing gives the same faces and positions.
  r = run_qsp("reorder --like " + quote(suzanne) + " " + quote(p("in.obj")) + " -o " + quote(p("out.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(run_qsp("decompress " + quote(p("out.qsp")) + " " + quote(p("back.obj"))).exit_code, 0);
  const Poly back = testing::read_faces(p("back.obj"));
  EXPECT_EQ(back.offsets, out.offsets);
  EXPECT_EQ(back.corners, out.corners);
  EXPECT_EQ(back.positions, out.positions);
  // IN with texture coordinates: kept (a value no corner names too), unless dropped.
  testing::spit(p("uv.obj"), "vt 0 0.5\n" + obj_text(in));
  r = run_qsp("reorder --like " + quote(suzanne) + " " + quote(p("uv.obj")) + " -o " + quote(p("o2.obj")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(testing::slurp(p("o2.obj")).find("vt 0 0.5\n"), std::string::npos);
  r = run_qsp("reorder --drop uv --like " + quote(suzanne) + " " + quote(p("uv.obj")) + " -o " +
              quote(p("o2.obj")) + " -f");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(testing::slurp(p("o2.obj")).find("vt "), std::string::npos);
  // Another topology: exit 1 with the level.
  Poly c;
  ASSERT_TRUE(flip_a_diagonal(in, c));
  testing::spit(p("flip.obj"), obj_text(c));
  r = run_qsp("reorder --like " + quote(suzanne) + " " + quote(p("flip.obj")) + " -o " + quote(p("o3.obj")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("is not isomorphic to"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("o3.obj")));
}

}  // namespace
}  // namespace qsp
