// Tests for qsp/io.h: strict OBJ/OFF/PLY reading, exact round trips, atomic writes, and every file in
// testdata/invalid/ being refused with the code and location its .expect sidecar names.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"
#include "support/corpus.h"
#include "support/files.h"
#include "support/float32_text.h"
#include "support/openmesh.h"

namespace fs = std::filesystem;

namespace {

std::uint32_t bits(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

// Runs `fn`, expecting qsp::Error with `code`; returns its message.
template <typename Fn>
std::string expect_error(Fn&& fn, qsp::ErrorCode code) {
  try {
    fn();
  } catch (const qsp::Error& e) {
    EXPECT_EQ(qsp::error_name(e.code()), std::string(qsp::error_name(code))) << e.what();
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected qsp::Error, got std::exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected qsp::Error(" << qsp::error_name(code) << "), nothing thrown";
  return {};
}

using qsp::testing::slurp;
using qsp::testing::spit;
using qsp::testing::TempDir;

std::vector<std::uint32_t> quads(const qsp::QuadMesh& m) { return m.quads; }

}  // namespace

// ---------------------------------------------------------------------------------------------
// OBJ acceptance

TEST(ReadObj, PlainQuadsAndUnreferencedVertex) {
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 5 5 5\n"
      "f 1 2 3 4\n";
  qsp::ReadReport r;
  const qsp::QuadMesh m = qsp::read_obj(text, "t.obj", &r);
  EXPECT_EQ(m.vertex_count(), 5u);  // unreferenced vertex kept
  ASSERT_EQ(m.face_count(), 1u);
  EXPECT_EQ(quads(m), (std::vector<std::uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(r.face_line, (std::vector<std::uint32_t>{6}));
  EXPECT_FALSE(r.has_extra_data());
  EXPECT_EQ(r.categories(), 0u);
  EXPECT_EQ(r.describe_extra_data("t.obj"), "");
}

TEST(ReadObj, FloatsRoundExactlyAsFromChars) {
  const char* tokens[] = {"0.1",  "-0", "1e-45", "3.4028235e38",   "16777217",
                          "+2.5", ".5", "1.",    "-1.17549435e-38"};
  for (const char* t : tokens) {
    const std::string text = std::string("v ") + t + " 0 0\n";
    const qsp::QuadMesh m = qsp::read_obj(text, "t.obj");
    const char* s = t[0] == '+' ? t + 1 : t;
    float want = 0;
    std::from_chars(s, s + std::strlen(s), want);
    EXPECT_EQ(bits(m.positions[0]), bits(want)) << t;
  }
}

TEST(ReadObj, AttributeSyntaxNegativeIndicesAndExtras) {
  const std::string text =
      "# header comment\n"
      "mtllib a.mtl\n"
      "o thing\n"
      "v 0 0 0 1\n"            // w
      "v 1 0 0 0.5 0.5 0.5\n"  // colour
      "v 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
      "vt 0 0\nvt 1 0\nvt 1 1 0\n"
      "vn 0 0 1\n"
      "vp 0.5\n"
      "g group1\n"
      "usemtl red\n"
      "s 1\n"
      "f 1/1 2/2 3/3 4/1\n"
      "f 2//1 5//1 6//1 3//1\n"
      "f -5/1/1 -4/2/1 -1/3/1 -3/1/1\n"  // relative: 2 5 6 3... resolved against 6 vertices
      "s off\n"
      "t crease 2/1/0 1 2 4.0\n"
      "t interpolateboundary 1/0/0 1\n";
  qsp::ReadReport r;
  const qsp::QuadMesh m = qsp::read_obj(text, "t.obj", &r);
  ASSERT_EQ(m.face_count(), 3u);
  EXPECT_EQ(quads(m), (std::vector<std::uint32_t>{0, 1, 2, 3, 1, 4, 5, 2, 1, 2, 5, 3}));
  EXPECT_EQ(r.texcoords, 3u);
  EXPECT_EQ(r.normals, 1u);
  EXPECT_EQ(r.kept_lines, 1u);  // vp
  EXPECT_EQ(r.first_kept.line, 14u);
  EXPECT_EQ(r.faces_with_texcoords, 2u);
  EXPECT_EQ(r.faces_with_normals, 2u);
  EXPECT_EQ(r.groups, 2u);
  EXPECT_EQ(r.materials, 2u);
  EXPECT_EQ(r.smoothing, 2u);
  EXPECT_EQ(r.tags, 2u);
  EXPECT_EQ(r.vertex_colors, 1u);
  EXPECT_EQ(r.vertex_weights, 1u);
  EXPECT_EQ(r.face_line, (std::vector<std::uint32_t>{18, 19, 20}));
  EXPECT_TRUE(r.has_extra_data());
  EXPECT_EQ(r.categories(), qsp::kCategoryAll);
  EXPECT_EQ(r.leading_comments, std::vector<std::string>{" header comment"});
  EXPECT_EQ(r.describe_extra_data("t.obj"),
            "3 texture coordinates, 2 faces with texture coordinate indices (uv), 1 normal, 2 faces with "
            "normal indices (normal), 1 vertex colour (color), 2 group/object statements (group), 2 material "
            "statements (material), 2 smoothing group statements (smoothing), 2 subdivision tags (tag), 1 "
            "leading comment line (comment), 1 "
            "vertex weight (v x y z w), 1 line qsp keeps only as text, the first at t.obj:14: `vp` "
            "(parameter-space vertex) (extra)");
  EXPECT_EQ(r.describe_extra_data("t.obj", qsp::kCategoryUv | qsp::kCategoryTag),
            "3 texture coordinates, 2 faces with texture coordinate indices (uv), 2 subdivision tags (tag)");
}

// Lines without geometry that qsp does not understand are counted as kept lines (the exact reader
// keeps them as text), the first one's line and what it is noted; what would change the mesh is refused.
TEST(ReadObj, LinesWithoutGeometryAreCountedNotRefused) {
  const std::string square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
  struct Case {
    std::string lines;
    std::uint64_t count;
    const char* first;  // what the first kept line is
  };
  const Case cases[] = {
      {"This asset was made by hand\n", 1, "unknown statement 'This'"},
      {"foo 1 2\n", 1, "unknown statement 'foo'"},
      {"\xff\x10 garbage\n", 1, "unknown statement '\\xff\\x10'"},
      {"cstype bspline\ndeg 3\nend\n", 3, "`cstype` (free-form or display attribute, no geometry)"},
      {"vp 0.5 0.5\nvp 1\n", 2, "`vp` (parameter-space vertex)"},
      {"usemap tex\nmaplib lib\n", 2, "`usemap` (old texture map statement)"},
      {"t crease 3/1/0 0 1 2 1\n", 1, "malformed OpenSubdiv tag"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.lines);
    const std::string text = square + c.lines + "f 1 2 3 4\n";
    qsp::ReadReport r;
    const qsp::QuadMesh m = qsp::read_obj(text, "t.obj", &r);
    EXPECT_EQ(quads(m), (std::vector<std::uint32_t>{0, 1, 2, 3}));
    EXPECT_EQ(r.kept_lines, c.count);
    EXPECT_EQ(r.first_kept.line, 5u);
    EXPECT_EQ(r.first_kept.message, c.first);
    EXPECT_EQ(r.categories(), unsigned{qsp::kCategoryExtra});
    EXPECT_EQ(r.tags, 0u);
    EXPECT_EQ(r.materials, 0u);
    // The exact reader keeps the same lines, the first at the same line.
    qsp::ReadNotes notes;
    const qsp::Mesh exact = qsp::read_obj_mesh(text, "t.obj", &notes);
    EXPECT_EQ(exact.verbatim.size(), c.count);
    ASSERT_FALSE(notes.warnings.empty());
    EXPECT_EQ(notes.warnings[0].line, r.first_kept.line);
    EXPECT_EQ(notes.warnings[0].message, "kept as text and written back unchanged: " + std::string(c.first));
  }
  // A NUL byte is no prose: a binary file read as OBJ is refused by both readers, at its line.
  const std::string binary = square + std::string("\x00\xff\x10 garbage\n", 12) + "f 1 2 3 4\n";
  for (const bool exact : {false, true}) {
    try {
      if (exact) {
        (void)qsp::read_obj_mesh(binary, "t.obj");
      } else {
        (void)qsp::read_obj(binary, "t.obj");
      }
      ADD_FAILURE() << "a NUL byte was kept as text (exact reader: " << exact << ")";
    } catch (const qsp::Error& e) {
      EXPECT_EQ(e.code(), qsp::ErrorCode::kParse);
      EXPECT_EQ(std::string(e.what()),
                "t.obj:5: binary data (a NUL byte) where a statement should be: not OBJ text");
    }
  }
  for (const char* geometry : {"curv 0 1 1 2\n", "curv2 1 2\n", "surf 0 1 0 1 1 2 3\n", "l 1 2\n", "p 1\n"}) {
    SCOPED_TRACE(geometry);
    EXPECT_THROW(qsp::read_obj(square + "cstype bspline\n" + geometry, "t.obj"), qsp::Error);
  }
}

TEST(ReadObj, CrlfTabsTrailingSpaceContinuationBomForwardRefs) {
  const std::string text =
      "\xEF\xBB\xBF# BOM, CRLF, tabs\r\n"
      "f 1 2 3 4\r\n"  // forward references: vertices come later
      "v\t0 0 0   \r\n"
      "\r\n"
      "   v 1 0 0\t\r\n"
      "v 1 1 0 # trailing comment\r\n"
      "v 0 1 0\r\n"
      "v 2 0 0\nv 2 1 0\n"
      "f 2 5 \\\r\n"
      "   6 3\r\n"
      "f 2 5 6 3\\\n"  // continuation right after a token, joined with an empty line
      "\n"
      "f 1 2 3 4";  // no final newline
  qsp::ReadReport r;
  const qsp::QuadMesh m = qsp::read_obj(text, "t.obj", &r);
  EXPECT_EQ(m.vertex_count(), 6u);
  EXPECT_EQ(quads(m), (std::vector<std::uint32_t>{0, 1, 2, 3, 1, 4, 5, 2, 1, 4, 5, 2, 0, 1, 2, 3}));
  EXPECT_EQ(r.face_line, (std::vector<std::uint32_t>{2, 10, 12, 14}));
  EXPECT_EQ(m.positions[3], 1.0f);
}

TEST(ReadObj, ContinuationJoinsLinesAndKeepsLineNumbers) {
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
      "f 1 2 \\\n"
      "  3 4\n"
      "f 4 \\\r\n 3 \\\n 2 1\n"
      "x_after";  // line 10: must be reported there
  qsp::ReadReport r;
  const qsp::QuadMesh m = qsp::read_obj(text, "t.obj", &r);
  EXPECT_EQ(quads(m), (std::vector<std::uint32_t>{0, 1, 2, 3, 3, 2, 1, 0}));
  EXPECT_EQ(r.face_line, (std::vector<std::uint32_t>{5, 7}));
  EXPECT_EQ(r.kept_lines, 1u);
  EXPECT_EQ(r.first_kept.line, 10u);
  EXPECT_EQ(r.first_kept.message, "unknown statement 'x_after'");
  const std::string msg = expect_error(
      [&] { qsp::read_obj(text.substr(0, text.size() - 7) + "v 1 x", "t.obj"); }, qsp::ErrorCode::kParse);
  EXPECT_NE(msg.find("t.obj:10: "), std::string::npos) << msg;
}

// A CR alone ends a line (classic Mac OS), as LF and CRLF do. Read as a blank, it once let a comment
// or a counted statement (g, o, usemtl, ...) swallow the lines after it: faces silently lost.
TEST(ReadObj, LoneCarriageReturnEndsALine) {
  const std::string quad = "v 0 0 0\rv 1 0 0\rv 1 1 0\rv 0 1 0\rf 1 2 3 4\r";
  qsp::ReadReport r;
  qsp::QuadMesh m = qsp::read_obj("# exported by OldMacTool\r" + quad, "t.obj", &r);
  EXPECT_EQ(m.vertex_count(), 4u);
  EXPECT_EQ(quads(m), (std::vector<std::uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(r.face_line, (std::vector<std::uint32_t>{6}));
  // Mixed line ends: the face after a CR-ended comment is kept, and counted statements end there too.
  m = qsp::read_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 1 2 3 4\n# second\rf 2 5 6 3\n",
                    "t.obj");
  EXPECT_EQ(m.face_count(), 2u);
  m = qsp::read_obj("o cube\r" + quad, "t.obj", &r);
  EXPECT_EQ(m.face_count(), 1u);
  EXPECT_EQ(r.groups, 1u);
  // Line numbers count lone CRs, and a backslash before one continues the statement.
  const std::string msg =
      expect_error([&] { qsp::read_obj(quad + "f 1 2 x 4\r", "t.obj"); }, qsp::ErrorCode::kParse);
  EXPECT_NE(msg.find("t.obj:6: malformed integer 'x'"), std::string::npos) << msg;
  m = qsp::read_obj("v 0 0 \\\r 0\rv 1 0 0\r\rv 1 1 0\rv 0 1 0\rf 1 2 3 4", "t.obj", &r);
  EXPECT_EQ(m.vertex_count(), 4u);
  EXPECT_EQ(r.face_line, (std::vector<std::uint32_t>{7}));
  // Many CR-ended comments: each ends at its own CR (a search for the LF once scanned to the end of
  // the file for every comment).
  std::string many;
  for (int i = 0; i < 20000; ++i) many += "# c\r";
  m = qsp::read_obj(many + quad, "t.obj", &r);
  EXPECT_EQ(m.face_count(), 1u);
  EXPECT_EQ(r.face_line, (std::vector<std::uint32_t>{20005}));
}

TEST(ReadObj, EmptyAndCommentOnlyInputs) {
  EXPECT_EQ(qsp::read_obj("", "t.obj").vertex_count(), 0u);
  EXPECT_EQ(qsp::read_obj("# nothing\n\n   \n", "t.obj").face_count(), 0u);
}

TEST(ReadObj, NonQuadMessageCountsAllAndShowsThree) {
  std::string text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 2 2\n";
  for (int i = 0; i < 32; ++i) text += "f 1 2 3\n";
  const std::string msg = expect_error([&] { qsp::read_obj(text, "x.obj"); }, qsp::ErrorCode::kNotQuad);
  EXPECT_EQ(msg.rfind("x.obj:6: 32 faces are not quads (first: line 6: triangle, line 7: triangle, line 8: "
                      "triangle, ...); qsp stores quad meshes only and never triangulates or drops faces",
                      0),
            0u)
      << msg;
}

TEST(ReadObj, HostileInputNeverCrashes) {
  // Random bytes drawn from OBJ's alphabet: every outcome is a mesh or a qsp::Error.
  std::mt19937 rng(12345);
  const std::string alphabet = "vf t#/\\-+.0123456789e\n\r\tnaix";
  for (int round = 0; round < 3000; ++round) {
    std::string text;
    const int len = static_cast<int>(rng() % 80);
    for (int i = 0; i < len; ++i) text += alphabet[rng() % alphabet.size()];
    for (auto reader : {&qsp::read_obj, &qsp::read_off}) {
      try {
        (void)reader(text, "fuzz", nullptr);
      } catch (const qsp::Error&) {
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// OFF acceptance

TEST(ReadOff, MultiLineFacesColoursAndComments) {
  const std::string text =
      "# leading comment\n"
      "OFF\n"
      "# counts next\n"
      "5 3 0\n"
      "0 0 0\n1 0 0\n1 1 0\n0 1 0\n\n2 2 2  # trailing comment\n"
      "4 0 1\n2\n3\n"                 // face over three lines
      "4 1 4 2 0 255 0 0\n"           // face colour (RGB)
      "4\n3 2\n4 1 0.5 0.5 0.5 1\n";  // colour (RGBA) on the last index line
  qsp::ReadReport r;
  const qsp::QuadMesh m = qsp::read_off(text, "t.off", &r);
  EXPECT_EQ(m.vertex_count(), 5u);
  EXPECT_EQ(quads(m), (std::vector<std::uint32_t>{0, 1, 2, 3, 1, 4, 2, 0, 3, 2, 4, 1}));
  EXPECT_EQ(r.face_line, (std::vector<std::uint32_t>{11, 14, 15}));
  EXPECT_EQ(r.face_colors, 2u);
}

TEST(ReadOff, CountsOnHeaderLineAndVariants) {
  qsp::ReadReport r;
  qsp::QuadMesh m = qsp::read_off("OFF 4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n", "t.off", &r);
  EXPECT_EQ(m.face_count(), 1u);
  m = qsp::read_off(
      "COFF\r\n4 1\r\n0 0 0 1 0 0 1\r\n1 0 0 1 0 0 1\r\n1 1 0 1 0 0 1\r\n0 1 0 1 0 0\r\n4 0 1 2 3\r\n",
      "t.off", &r);
  EXPECT_EQ(r.vertex_colors, 4u);
  m = qsp::read_off("NOFF\n4 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n4 0 1 2 3\n", "t.off",
                    &r);
  EXPECT_EQ(r.normals, 4u);
  EXPECT_EQ(m.positions[3], 1.0f);
}

TEST(ReadOff, SharedIglMultiLineFile) {
  QSP_NEEDS_SHARED();
  const fs::path p = qsp::testing::shared_dir() / "meshes" / "igl_inspired_mesh_quads_conjugate.off";
  const qsp::QuadMesh m = qsp::read_mesh_file(p.string());
  EXPECT_EQ(m.vertex_count(), 1749u);
  EXPECT_EQ(m.face_count(), 1633u);
}

// ---------------------------------------------------------------------------------------------
// Round trips

namespace {

qsp::QuadMesh random_mesh(std::mt19937& rng, std::size_t vertices, std::size_t faces) {
  qsp::QuadMesh m;
  const float specials[] = {0.0f,
                            -0.0f,
                            1.0f,
                            std::numeric_limits<float>::denorm_min(),
                            -std::numeric_limits<float>::denorm_min(),
                            std::numeric_limits<float>::min(),
                            std::nextafter(std::numeric_limits<float>::min(), 0.0f),  // largest subnormal
                            std::numeric_limits<float>::max(),
                            -std::numeric_limits<float>::max(),
                            16777216.0f,
                            0.1f,
                            1e-30f};
  for (float f : specials) m.positions.push_back(f);
  while (m.positions.size() < 3 * vertices) {
    const std::uint32_t b = static_cast<std::uint32_t>(rng());
    float f;
    std::memcpy(&f, &b, 4);
    if (std::isfinite(f)) m.positions.push_back(f);  // any finite bit pattern, subnormals included
  }
  m.positions.resize(3 * vertices);
  for (std::size_t f = 0; f < faces; ++f) {
    std::uint32_t q[4];
    for (int i = 0; i < 4; ++i) {
      bool fresh;
      do {
        q[i] = static_cast<std::uint32_t>(rng() % vertices);
        fresh = true;
        for (int j = 0; j < i; ++j) fresh = fresh && q[j] != q[i];
      } while (!fresh);
      m.quads.push_back(q[i]);
    }
  }
  return m;
}

void expect_bit_exact(const qsp::QuadMesh& a, const qsp::QuadMesh& b) {
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    ASSERT_EQ(bits(a.positions[i]), bits(b.positions[i])) << "coordinate " << i << " = " << a.positions[i];
  }
  EXPECT_EQ(a.quads, b.quads);
}

}  // namespace

TEST(RoundTrip, ObjIsBitExactOnRandomFloats) {
  std::mt19937 rng(7);
  for (int round = 0; round < 5; ++round) {
    const qsp::QuadMesh m = random_mesh(rng, 5000, 3000);
    const std::string text = qsp::write_obj(m);
    qsp::ReadReport r;
    expect_bit_exact(m, qsp::read_obj(text, "rt.obj", &r));
    EXPECT_FALSE(r.has_extra_data());
  }
}

TEST(RoundTrip, OffIsBitExactOnRandomFloats) {
  std::mt19937 rng(8);
  const qsp::QuadMesh m = random_mesh(rng, 4000, 2000);
  expect_bit_exact(m, qsp::read_off(qsp::write_off(m), "rt.off"));
}

TEST(RoundTrip, WriterFormat) {
  qsp::QuadMesh m;
  m.positions = {0.0f, 0.5f, -1.0f, 1.0f, 0.1f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f, 8.0f};
  m.quads = {0, 1, 2, 3};
  EXPECT_EQ(qsp::write_obj(m), "v 0 0.5 -1\nv 1 0.1 2\nv 3 4 5\nv 6 7 8\nf 1 2 3 4\n");
  EXPECT_EQ(qsp::write_off(m), "OFF\n4 1 0\n0 0.5 -1\n1 0.1 2\n3 4 5\n6 7 8\n4 0 1 2 3\n");
}

TEST(RoundTrip, WritersRefuseWhatWouldNotReadBack) {
  qsp::QuadMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0};
  m.quads = {0, 1, 2, 3};
  expect_error([&] { qsp::write_obj(m); }, qsp::ErrorCode::kBadIndex);
  m.positions.insert(m.positions.end(), {std::nanf(""), 0, 0});
  expect_error([&] { qsp::write_off(m); }, qsp::ErrorCode::kBadNumber);
}

// ---------------------------------------------------------------------------------------------
// PLY

namespace {

std::string ply_ascii(const std::string& vertex_props, const std::string& vertices, int vcount,
                      const std::string& faces, int fcount, const std::string& face_props = "") {
  return "ply\nformat ascii 1.0\ncomment test\nelement vertex " + std::to_string(vcount) + "\n" +
         vertex_props + "element face " + std::to_string(fcount) +
         "\nproperty list uchar int vertex_indices\n" + face_props + "end_header\n" + vertices + faces;
}

}  // namespace

TEST(ReadPly, AsciiKeepsFileCornerOrder) {
  TempDir dir;
  const fs::path p = dir.path() / "a.ply";
  spit(p, ply_ascii("property float x\nproperty float y\nproperty float z\n",
                    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n2 1 0.1\n", 6, "4 2 3 0 1\n4 4 5 2 1\n", 2));
  qsp::ReadReport r;
  const qsp::QuadMesh m = qsp::read_mesh_file(p.string(), &r);
  EXPECT_EQ(quads(m), (std::vector<std::uint32_t>{2, 3, 0, 1, 4, 5, 2, 1}));
  EXPECT_EQ(bits(m.positions[17]), bits(0.1f));
  EXPECT_EQ(r.categories(), qsp::kCategoryComment);  // the header's comment line, kept
  EXPECT_EQ(r.leading_comments, std::vector<std::string>{"test"});
}

TEST(ReadPly, BinaryLittleEndianDoublesAndColours) {
  TempDir dir;
  const fs::path p = dir.path() / "b.ply";
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
      "property double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  const double v[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.25}};
  for (const auto& row : v) {
    bytes.append(reinterpret_cast<const char*>(row), sizeof row);
    bytes.append("\x01\x02\x03", 3);
  }
  bytes.push_back(4);
  const std::int32_t f[4] = {1, 2, 3, 0};
  bytes.append(reinterpret_cast<const char*>(f), sizeof f);
  spit(p, bytes);
  qsp::ReadReport r;
  const qsp::QuadMesh m = qsp::read_ply_file(p.string(), &r);
  EXPECT_EQ(quads(m), (std::vector<std::uint32_t>{1, 2, 3, 0}));
  EXPECT_EQ(m.positions[11], 0.25f);
  EXPECT_EQ(r.vertex_colors, 4u);
}

// Doubles round to the nearest float as text does, and are refused where text is: a nonzero value
// that rounds to zero, or one that rounds to infinity, would silently change the mesh.
TEST(ReadPly, BinaryDoublesOutsideTheFloatRangeAreRefused) {
  TempDir dir;
  const fs::path p = dir.path() / "d.ply";
  for (const double y : {1e-300, 1e39, 1e-40}) {
    std::string bytes =
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
        "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const double v[4][3] = {{0, y, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    bytes.append(reinterpret_cast<const char*>(v), sizeof v);
    bytes.push_back(4);
    const std::int32_t f[4] = {0, 1, 2, 3};
    bytes.append(reinterpret_cast<const char*>(f), sizeof f);
    spit(p, bytes);
    if (y == 1e-40) {  // a subnormal float: kept, as from_chars keeps "1e-40"
      EXPECT_EQ(qsp::read_ply_file(p.string()).positions[1], static_cast<float>(1e-40));
      continue;
    }
    const std::string msg = expect_error([&] { qsp::read_ply_file(p.string()); }, qsp::ErrorCode::kBadNumber);
    EXPECT_NE(msg.find("vertex 0 has a coordinate outside the float32 range"), std::string::npos) << msg;
  }
}

// A property declared twice would be read past and its values dropped; and the last ASCII value
// needs no newline after it.
TEST(ReadPly, DuplicatePropertyRefusedAndLastValueNeedsNoNewline) {
  TempDir dir;
  const fs::path p = dir.path() / "a.ply";
  spit(p, ply_ascii("property float x\nproperty float y\nproperty float z\nproperty float x\n",
                    "0 0 0 9\n1 0 0 9\n1 1 0 9\n0 1 0 9\n", 4, "4 0 1 2 3\n", 1));
  const std::string msg = expect_error([&] { qsp::read_ply_file(p.string()); }, qsp::ErrorCode::kParse);
  EXPECT_NE(msg.find(":8: PLY element 'vertex' declares property 'x' twice"), std::string::npos) << msg;
  spit(p,
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
       "end_header\n0 0 7");
  EXPECT_EQ(qsp::read_ply_file(p.string()).positions, (std::vector<float>{0, 0, 7}));
  EXPECT_EQ(qsp::read_off("OFF\n1 0 0\n0 0 7", "t.off").positions, (std::vector<float>{0, 0, 7}));
}

// ASCII PLY reads a leading '+' as OBJ and OFF do; refuses an integer its declared type cannot hold
// (a binary file cannot have one) and text after end_header on its line.
TEST(ReadPly, AsciiSignsTypeRangesAndEndHeader) {
  TempDir dir;
  const fs::path p = dir.path() / "a.ply";
  const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
  spit(p, ply_ascii(xyz, "+0 0 0\n1 +0 0\n1 1 +.5\n0 1 0\n", 4, "+4 0 +1 2 3\n", 1));
  const qsp::QuadMesh m = qsp::read_ply_file(p.string());
  EXPECT_EQ(m.positions[8], 0.5f);
  EXPECT_EQ(quads(m), (std::vector<std::uint32_t>{0, 1, 2, 3}));
  const auto refused = [&](const std::string& text, const std::string& expected) {
    spit(p, text);
    const std::string msg = expect_error([&] { qsp::read_ply_file(p.string()); }, qsp::ErrorCode::kParse);
    EXPECT_NE(msg.find(expected), std::string::npos) << msg;
  };
  refused(ply_ascii(xyz, "+-1 0 0\n1 0 0\n1 1 0\n0 1 0\n", 4, "4 0 1 2 3\n", 1),
          "malformed number '+-1' in vertex 0");
  refused(ply_ascii(xyz, "0 0 0\n1 0 0\n1 1 0\n0 1 0\n", 4, "260 0 1 2 3\n", 1),
          "integer 260 in face 0 is out of range for its PLY type uchar");
  refused(
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty char x\nproperty char y\nproperty char z\n"
      "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 -129\n",
      "integer -129 in vertex 3 is out of range for its PLY type char");
  refused(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
      "end_header extra\n0 0 0\n",
      ":7: unexpected text after end_header");
}

TEST(ReadPly, BinaryBigEndianIntCoordinatesAndUnknownProperties) {
  TempDir dir;
  const fs::path p = dir.path() / "be.ply";
  std::string bytes =
      "ply\nformat binary_big_endian 1.0\nobj_info made by hand\nelement vertex 4\nproperty short x\n"
      "property short y\nproperty short z\nproperty float quality\nelement face 1\n"
      "property list uchar uint vertex_indices\nend_header\n";
  const int v[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, -7}};
  for (const auto& row : v) {
    for (int c : row) {
      bytes.push_back(static_cast<char>((c >> 8) & 0xff));
      bytes.push_back(static_cast<char>(c & 0xff));
    }
    bytes.append("\x3f\x80\x00\x00", 4);  // 1.0f
  }
  bytes.push_back(4);
  for (int c : {3, 0, 1, 2}) bytes.append({0, 0, 0, static_cast<char>(c)});
  spit(p, bytes);
  qsp::ReadReport r;
  const qsp::QuadMesh m = qsp::read_ply_file(p.string(), &r);
  EXPECT_EQ(quads(m), (std::vector<std::uint32_t>{3, 0, 1, 2}));
  EXPECT_EQ(m.positions[11], -7.0f);
  EXPECT_EQ(r.other_properties, 4u);
  EXPECT_EQ(r.face_line, (std::vector<std::uint32_t>{0}));
}

TEST(ReadPly, AsciiFaceLinesAndExactFloats) {
  TempDir dir;
  const fs::path p = dir.path() / "lines.ply";
  spit(p, ply_ascii("property double x\nproperty double y\nproperty double z\n",
                    "0.1 0 0\n1 0 0\r\n1 1 0\n0 1 0\n2 0 0\n2 1 1e-45\n", 6, "\n4 0 1 2 3\n4 1 4 5 2\n", 2));
  qsp::ReadReport r;
  const qsp::QuadMesh m = qsp::read_ply_file(p.string(), &r);
  EXPECT_EQ(bits(m.positions[0]), bits(0.1f));
  EXPECT_EQ(bits(m.positions[17]), bits(std::numeric_limits<float>::denorm_min()));
  EXPECT_EQ(r.face_line, (std::vector<std::uint32_t>{18, 19}));
}

namespace {

void write_ply(const fs::path& p, const qsp::QuadMesh& m, bool binary) {
  std::string out = std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") +
                    " 1.0\nelement vertex " + std::to_string(m.vertex_count()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(m.face_count()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (std::size_t i = 0; i < m.positions.size(); i += 3) {
    if (binary) {
      out.append(reinterpret_cast<const char*>(&m.positions[i]), 12);
    } else {
      char buf[128];
      std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g\n", m.positions[i], m.positions[i + 1],
                    m.positions[i + 2]);
      out += buf;
    }
  }
  for (std::size_t i = 0; i < m.quads.size(); i += 4) {
    if (binary) {
      out.push_back(4);
      out.append(reinterpret_cast<const char*>(&m.quads[i]), 16);
    } else {
      out += "4 " + std::to_string(m.quads[i]) + " " + std::to_string(m.quads[i + 1]) + " " +
             std::to_string(m.quads[i + 2]) + " " + std::to_string(m.quads[i + 3]) + "\n";
    }
  }
  spit(p, out);
}

}  // namespace

TEST(ReadPly, AgreesWithObjAndOpenMeshOnSharedMesh) {
  // A real mesh written as ASCII and binary PLY reads back as the OBJ did, and as OpenMesh reads it.
  QSP_NEEDS_SHARED();
  const fs::path src = qsp::testing::shared_dir() / "meshes" / "igl_horse_quad.obj";
  const qsp::QuadMesh obj = qsp::read_mesh_file(src.string());
  TempDir dir;
  for (const bool binary : {false, true}) {
    const fs::path p = dir.path() / (binary ? "horse_bin.ply" : "horse_ascii.ply");
    write_ply(p, obj, binary);
    const qsp::QuadMesh ply = qsp::read_mesh_file(p.string());
    expect_bit_exact(obj, ply);
    expect_bit_exact(ply, qsp::testing::read_with_openmesh(p));
  }
}

TEST(ReadPly, MutatedFilesNeverCrash) {
  std::mt19937 rng(2024);
  qsp::QuadMesh m = random_mesh(rng, 20, 10);
  TempDir dir;
  for (const bool binary : {false, true}) {
    const fs::path good = dir.path() / "good.ply";
    write_ply(good, m, binary);
    const std::string original = slurp(good);
    const fs::path p = dir.path() / "mutated.ply";
    for (int round = 0; round < 200; ++round) {
      std::string bytes = original;
      const int edits = 1 + static_cast<int>(rng() % 4);
      for (int e = 0; e < edits; ++e) {
        const std::size_t at = rng() % bytes.size();
        switch (rng() % 3) {
          case 0:
            bytes[at] = static_cast<char>(rng());
            break;
          case 1:
            bytes.erase(at, 1 + rng() % 8);
            break;
          default:
            bytes.resize(at);
            break;
        }
        if (bytes.empty()) bytes.push_back('p');
      }
      spit(p, bytes);
      try {
        (void)qsp::read_ply_file(p.string());
      } catch (const qsp::Error&) {
      }
    }
  }
}

TEST(ReadPly, NonManifoldInputIsKeptAsWritten) {
  // Three quads on one edge: OpenMesh would duplicate vertices; qsp's reader keeps the file as it is
  // and leaves the refusal to build_adjacency (kNonManifold), as for OBJ/OFF.
  TempDir dir;
  const fs::path p = dir.path() / "nm.ply";
  spit(p, ply_ascii("property float x\nproperty float y\nproperty float z\n",
                    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n1 -1 0\n0 -1 0\n1 0 1\n0 0 1\n", 8,
                    "4 0 1 2 3\n4 1 0 5 4\n4 0 1 6 7\n", 3));
  const qsp::QuadMesh m = qsp::read_mesh_file(p.string());
  EXPECT_EQ(m.vertex_count(), 8u);
  EXPECT_EQ(quads(m), (std::vector<std::uint32_t>{0, 1, 2, 3, 1, 0, 5, 4, 0, 1, 6, 7}));
  EXPECT_NE(qsp::testing::read_with_openmesh(p).vertex_count(), 8u);  // what qsp avoids
}

// ---------------------------------------------------------------------------------------------
// Invalid files: each NAME.{obj,off,ply} has NAME.expect with `code=` and `message=` lines.

TEST(InvalidFiles, EachIsRefusedWithExpectedCodeAndLocation) {
  const fs::path dir = fs::path(QSP_TESTDATA_DIR) / "invalid";
  ASSERT_TRUE(fs::is_directory(dir)) << dir;
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const fs::path p = entry.path();
    const std::string ext = p.extension().string();
    if (ext != ".obj" && ext != ".off" && ext != ".ply") continue;  // .qsp etc. belong to other suites
    SCOPED_TRACE(p.filename().string());
    fs::path expect_path = p;
    expect_path.replace_extension(".expect");
    ASSERT_TRUE(fs::exists(expect_path)) << "missing sidecar " << expect_path;
    auto expect = qsp::testing::read_expect(expect_path);
    ASSERT_TRUE(expect.count("code") && expect.count("message")) << expect_path;
    try {
      (void)qsp::read_mesh_file(p.string());
      ADD_FAILURE() << p << " was accepted";
    } catch (const qsp::Error& e) {
      EXPECT_EQ(qsp::error_name(e.code()), expect["code"]) << e.what();
      EXPECT_NE(std::string(e.what()).find(expect["message"]), std::string::npos)
          << "message: " << e.what() << "\nexpected to contain: " << expect["message"];
    } catch (const std::exception& e) {
      ADD_FAILURE() << p << " threw a non-qsp exception: " << e.what();
    }
    ++checked;
  }
  EXPECT_GE(checked, 40);
}

// invalid/topology/: files the reader accepts and build_adjacency refuses, with the code= and message=
// of each sidecar.
TEST(InvalidFiles, TopologyDefectsAreRefusedWithExpectedCode) {
  const fs::path dir = fs::path(QSP_TESTDATA_DIR) / "invalid" / "topology";
  int checked = 0;
  for (const fs::path& p : qsp::testing::invalid_meshes()) {
    if (p.parent_path() != dir) continue;
    SCOPED_TRACE(p.filename().string());
    auto expect = qsp::testing::read_expect(fs::path(p).replace_extension(".expect"));
    ASSERT_TRUE(expect.count("code") && expect.count("message"));
    const qsp::QuadMesh m = qsp::read_mesh_file(p.string());
    // The CLI adds "file:line: " (cli::load_mesh); the library names faces and vertices.
    std::string want = expect["message"];
    if (const auto at = want.find(p.filename().string() + ":"); at != std::string::npos)
      want = want.substr(want.find(": ", at) + 2);
    try {
      (void)qsp::build_adjacency(m);
      ADD_FAILURE() << "accepted";
    } catch (const qsp::Error& e) {
      EXPECT_EQ(qsp::error_name(e.code()), expect["code"]) << e.what();
      EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what() << "\nexpected: " << want;
    }
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

// ---------------------------------------------------------------------------------------------
// Shared real-world meshes

namespace {

// The topology columns of a manifest row, counted here from the face lists alone (an edge map and a
// union-find), independently of qsp's half-edge adjacency.
struct Topology {
  long components = 0, edges = 0, boundary_edges = 0, boundary_loops = 0, euler = 0;
  long interior_irregular = 0, boundary_irregular = 0, corners = 0;
};

Topology count_topology(const qsp::QuadMesh& m) {
  const std::size_t nv = m.vertex_count();
  std::vector<std::uint32_t> root(nv);
  for (std::uint32_t v = 0; v < nv; ++v) root[v] = v;
  const auto find = [&](std::uint32_t v) {
    while (root[v] != v) v = root[v] = root[root[v]];
    return v;
  };
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> faces_on_edge;
  std::vector<bool> referenced(nv);
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    for (int c = 0; c < 4; ++c) {
      const std::uint32_t a = m.quads[4 * f + c], b = m.quads[4 * f + (c + 1) % 4];
      ++faces_on_edge[{std::min(a, b), std::max(a, b)}];
      root[find(a)] = find(b);
      referenced[a] = true;
    }
  }
  Topology t;
  std::vector<long> valence(nv), boundary_degree(nv);
  std::vector<std::uint32_t> loop_root(nv);
  for (std::uint32_t v = 0; v < nv; ++v) loop_root[v] = v;
  const auto find_loop = [&](std::uint32_t v) {
    while (loop_root[v] != v) v = loop_root[v] = loop_root[loop_root[v]];
    return v;
  };
  for (const auto& [e, n] : faces_on_edge) {
    ++valence[e.first], ++valence[e.second];
    if (n == 1) {
      ++t.boundary_edges;
      ++boundary_degree[e.first], ++boundary_degree[e.second];
      loop_root[find_loop(e.first)] = find_loop(e.second);
    }
  }
  t.edges = static_cast<long>(faces_on_edge.size());
  // The manifest's Euler characteristic is of the surface: bare (unreferenced) vertices do not count.
  t.euler = static_cast<long>(std::count(referenced.begin(), referenced.end(), true)) - t.edges +
            static_cast<long>(m.face_count());
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (!referenced[v]) continue;
    t.components += find(v) == v;
    if (boundary_degree[v] == 0) {
      t.interior_irregular += valence[v] != 4;
    } else {
      t.boundary_loops += find_loop(v) == v;
      t.boundary_irregular += valence[v] > 3;
      t.corners += valence[v] == 2;
    }
  }
  return t;
}

}  // namespace

// Every row of both manifests (../shared/meshes and osd_shapes/): a file the row calls a valid quad mesh
// is read with its V and F, and its components, edges, boundary edges and loops, Euler characteristic
// and irregular vertices counted from the faces as read equal the row's (and qsp's adjacency agrees on
// the components); any other file is refused with an error naming one of the defects the row lists.
// Every OBJ and OFF file of the corpus: the reader reports exactly the coordinates float32 does not keep
// (counted by testing::count_rounded_coordinates, which shares no code with it), and the first one's
// line, vertex and text. pmp_hole_capsule.off (ten digits) and the libigl OFF (seventeen) have some.
TEST(ReadReport, CountsEveryCoordinateFloat32DoesNotKeep) {
  int files = 0, with_rounding = 0;
  for (const fs::path& p : qsp::testing::corpus()) {
    if (p.extension() != ".obj" && p.extension() != ".off") continue;
    SCOPED_TRACE(p.string());
    qsp::ReadReport r;
    try {
      (void)qsp::read_mesh_file(p.string(), &r);
    } catch (const qsp::Error&) {
      continue;  // refused before its end: the count would be partial
    }
    const qsp::testing::RoundedCount want = qsp::testing::count_rounded_coordinates(p);
    EXPECT_EQ(r.rounded_coordinates, want.count);
    if (want.count) {
      EXPECT_EQ(r.first_rounded.line, want.first_line);
      EXPECT_EQ(r.first_rounded.vertex, want.first_vertex);
      EXPECT_EQ(r.first_rounded.value, want.first_token);
      ++with_rounding;
    }
    ++files;
  }
  EXPECT_GT(files, 20);
  EXPECT_GE(with_rounding, qsp::testing::shared_present() ? 2 : 0);
}

// Crafted texts: OFF vertex lines with colours (never counted: only positions) and comments, a 17-digit print
// of a float32's float64 (held), and a float64 halfway between two float32s whose shortest text reads as the
// other one (not held: the reader keeps the text's own float32).
TEST(ReadReport, CraftedCoordinatesAreNotedWhereFloat32RoundsThem) {
  qsp::ReadReport off;
  (void)qsp::read_off(
      "COFF\n4 1 0\n0 0 0 1 1 1  # origin\n1 0 0.5 0.123456789012 0.2 0.3\n1 1 0.10000000000000001 0 0 0\n"
      "0 1.2345678901 0 1 1 1 # x\n"
      "4 0 1 2 3\n",
      "t.off", &off);
  EXPECT_EQ(off.rounded_coordinates, 1u);
  EXPECT_EQ(off.first_rounded.line, 6u);
  EXPECT_EQ(off.first_rounded.vertex, 3u);
  EXPECT_EQ(off.first_rounded.value, "1.2345678901");
  qsp::ReadReport ply;
  (void)qsp::read_ply(
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0.10000000000000001\n1 1 0\n0 1 0\n4 0 1 2 3\n",
      "t.ply", &ply);
  EXPECT_EQ(ply.rounded_coordinates, 0u);
  qsp::ReadReport tie;
  (void)qsp::read_obj("v 29999999999.999999 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", "t.obj", &tie);
  EXPECT_EQ(tie.rounded_coordinates, 1u);
  EXPECT_TRUE(qsp::testing::float32_keeps("0.10000000000000001"));
  EXPECT_FALSE(qsp::testing::float32_keeps("29999999999.999999"));
  // A hostile token is quoted in part, as other messages quote tokens.
  qsp::ReadReport longer;
  (void)qsp::read_obj("v 0." + std::string(5000, '3') + " 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n",
                      "t.obj", &longer);
  EXPECT_EQ(longer.rounded_coordinates, 1u);
  EXPECT_LT(longer.describe_rounding("t.obj").size(), 200u);
}

// PLY: ASCII text as OBJ's, a binary float64 or an integer beyond 2^24 that float32 rounds; float32
// values and small integers never.
TEST(ReadReport, PlyNotesWhatFloat32Rounds) {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty int z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  qsp::ReadReport r;
  (void)qsp::read_ply(head + "0 0 0\n1 0.5 0\n1 1.00000001 16777217\n0 1 16777216\n4 0 1 2 3\n", "t.ply", &r);
  EXPECT_EQ(r.rounded_coordinates, 2u);
  EXPECT_EQ(r.first_rounded.line, 12u);
  EXPECT_EQ(r.first_rounded.vertex, 2u);
  EXPECT_EQ(r.first_rounded.value, "1.00000001");
  EXPECT_EQ(
      r.describe_rounding("t.ply"),
      "t.ply:12: vertex 2 has 1.00000001, which float32 holds only as 1 (and 1 more coordinate like it)");
  // The same numbers in binary: doubles 0.5 and 1e-8 apart, an int one past 2^24.
  std::string bin =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
      "property int z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  auto put = [&bin](const auto v) { bin.append(reinterpret_cast<const char*>(&v), sizeof v); };
  for (const auto& [x, y, z] : std::vector<std::tuple<double, double, int>>{
           {0, 0, 0}, {1, 0.5, 0}, {1, 1.00000001, 16777217}, {0, 1, 16777216}}) {
    put(x), put(y), put(z);
  }
  put(std::uint8_t{4});
  for (int i = 0; i < 4; ++i) put(i);
  qsp::ReadReport b;
  (void)qsp::read_ply(bin, "t.ply", &b);
  EXPECT_EQ(b.rounded_coordinates, 2u);
  EXPECT_EQ(b.first_rounded.line, 0u);
  EXPECT_EQ(b.first_rounded.vertex, 2u);
  EXPECT_EQ(b.first_rounded.value, "1.00000001");
}

TEST(SharedMeshes, EveryManifestRowHoldsForTheFileAsRead) {
  QSP_NEEDS_SHARED();
  std::size_t rows = 0, valid = 0;
  for (const fs::path& dir : qsp::testing::shared_mesh_dirs()) {
    const auto manifest = qsp::testing::read_manifest(dir / "MANIFEST.tsv");
    ASSERT_FALSE(manifest.empty()) << dir;
    for (const auto& [name, row] : manifest) {
      SCOPED_TRACE((dir / name).string());
      ++rows;
      qsp::QuadMesh m;
      try {
        m = qsp::read_mesh_file((dir / name).string());
        const qsp::Adjacency adj = qsp::build_adjacency(m);
        EXPECT_TRUE(row.valid()) << "accepted, but the manifest lists a defect";
        EXPECT_EQ(static_cast<long>(adj.component_count), row.num("components"));
      } catch (const qsp::Error& e) {
        EXPECT_FALSE(row.valid()) << e.what();
        std::vector<qsp::ErrorCode> listed;
        if (row.col.at("all_quad") != "True") listed.push_back(qsp::ErrorCode::kNotQuad);
        if (row.num("degenerate_faces") > 0) listed.push_back(qsp::ErrorCode::kDegenerateFace);
        if (row.num("nonmanifold_edges") + row.num("nonmanifold_vertices") > 0)
          listed.push_back(qsp::ErrorCode::kNonManifold);
        if (row.num("flipped_edges") > 0) listed.push_back(qsp::ErrorCode::kOrientation);
        EXPECT_NE(std::find(listed.begin(), listed.end(), e.code()), listed.end()) << e.what();
        continue;
      }
      ++valid;
      EXPECT_EQ(static_cast<long>(m.vertex_count()), row.num("V"));
      EXPECT_EQ(static_cast<long>(m.face_count()), row.num("F"));
      EXPECT_EQ(row.num("quads"), row.num("F"));
      const Topology t = count_topology(m);
      EXPECT_EQ(t.components, row.num("components"));
      if (row.col.count("E")) {
        EXPECT_EQ(t.edges, row.num("E"));
      }
      EXPECT_EQ(t.boundary_edges, row.num("boundary_edges"));
      EXPECT_EQ(t.boundary_loops, row.num("boundary_loops"));
      EXPECT_EQ(t.euler, row.num("euler"));
      EXPECT_EQ(t.interior_irregular, row.num("interior_irregular"));
      EXPECT_EQ(t.boundary_irregular, row.num("boundary_irregular"));
      EXPECT_EQ(t.corners, row.num("boundary_corners_val2"));
      EXPECT_EQ(t.interior_irregular + t.boundary_irregular, row.num("extraordinary"));
    }
  }
  const auto files = qsp::testing::shared_meshes();
  EXPECT_EQ(rows, files.size()) << "manifest rows against mesh files";
  EXPECT_EQ(static_cast<int>(valid), qsp::testing::expected_valid_count(files));
  std::printf("%zu manifest rows checked, %zu of them valid quad meshes\n", rows, valid);
}

// OpenMesh's own OBJ and OFF readers give every valid shared mesh the same positions (bit for bit) and
// the same faces, corner for corner, as qsp's reader.
TEST(SharedMeshes, OpenMeshReadsEveryValidFileAlike) {
  QSP_NEEDS_SHARED();
  int compared = 0;
  for (const fs::path& p : qsp::testing::shared_meshes()) {
    if (p.extension() == ".ply" || !qsp::testing::expected_valid(p)) continue;
    SCOPED_TRACE(p.string());
    expect_bit_exact(qsp::testing::read_with_openmesh(p), qsp::read_mesh_file(p.string()));
    ++compared;
  }
  EXPECT_EQ(compared, qsp::testing::expected_valid_count(qsp::testing::shared_meshes()));
}

// ---------------------------------------------------------------------------------------------
// Files, formats, atomic writes

TEST(Files, FormatFromPath) {
  EXPECT_EQ(qsp::format_from_path("a/b/Mesh.OBJ"), qsp::MeshFormat::kObj);
  EXPECT_EQ(qsp::format_from_path("x.off"), qsp::MeshFormat::kOff);
  EXPECT_EQ(qsp::format_from_path("x.Ply"), qsp::MeshFormat::kPly);
  EXPECT_EQ(qsp::format_from_path("x.qsp"), qsp::MeshFormat::kQsp);
  EXPECT_EQ(qsp::format_from_path("x.stl"), qsp::MeshFormat::kUnknown);
  EXPECT_EQ(qsp::format_from_path("dir.obj/noext"), qsp::MeshFormat::kUnknown);
  EXPECT_EQ(qsp::format_from_path(".obj"), qsp::MeshFormat::kUnknown);
  EXPECT_EQ(qsp::format_from_path("-"), qsp::MeshFormat::kUnknown);
}

TEST(Files, ReadErrorsNameThePath) {
  TempDir dir;
  const std::string missing = (dir.path() / "missing.obj").string();
  std::string msg = expect_error([&] { qsp::read_file_bytes(missing); }, qsp::ErrorCode::kIo);
  EXPECT_NE(msg.find(missing + ": No such file or directory"), std::string::npos) << msg;
  msg = expect_error([&] { qsp::read_file_bytes(dir.path().string()); }, qsp::ErrorCode::kIo);
  EXPECT_NE(msg.find("Is a directory"), std::string::npos) << msg;
  expect_error([&] { qsp::read_mesh_file(missing); }, qsp::ErrorCode::kIo);
  expect_error([&] { qsp::read_mesh_file((dir.path() / "x.stl").string()); }, qsp::ErrorCode::kUnsupported);
  expect_error([&] { qsp::read_mesh_file("-"); }, qsp::ErrorCode::kUnsupported);
  expect_error([&] { qsp::read_mesh_file((dir.path() / "x.qsp").string()); }, qsp::ErrorCode::kUnsupported);
}

TEST(Files, ReadFileBytesIsExact) {
  TempDir dir;
  std::string bytes(3 << 20, '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(i * 131 + 7);
  spit(dir.path() / "big.bin", bytes);
  EXPECT_EQ(qsp::read_file_bytes((dir.path() / "big.bin").string()), bytes);
  spit(dir.path() / "empty.obj", "");
  EXPECT_EQ(qsp::read_file_bytes((dir.path() / "empty.obj").string()), "");
}

TEST(Files, AtomicWriteCreatesRefusesAndOverwrites) {
  TempDir dir;
  const fs::path p = dir.path() / "out.obj";
  qsp::write_file_atomic(p.string(), "first", false);
  EXPECT_EQ(slurp(p), "first");
  const mode_t mask = ::umask(0);
  ::umask(mask);
  EXPECT_EQ(fs::status(p).permissions(), static_cast<fs::perms>(0666 & ~mask));

  const std::string msg =
      expect_error([&] { qsp::write_file_atomic(p.string(), "second", false); }, qsp::ErrorCode::kIo);
  EXPECT_NE(msg.find(p.string() + ": already exists"), std::string::npos) << msg;
  EXPECT_EQ(slurp(p), "first");

  qsp::write_file_atomic(p.string(), "third", true);
  EXPECT_EQ(slurp(p), "third");
  qsp::write_file_atomic(p.string(), "", true);
  EXPECT_EQ(slurp(p), "");
  // Overwriting replaces the name, not the file: another hard link keeps the old bytes, and a symbolic
  // link is replaced by the file, its destination untouched.
  const fs::path other = dir.path() / "other.obj", dest = dir.path() / "dest.obj",
                 link = dir.path() / "link.obj";
  qsp::write_file_atomic(p.string(), "old", true);
  fs::create_hard_link(p, other);
  qsp::write_file_atomic(p.string(), "new", true);
  EXPECT_EQ(slurp(p), "new");
  EXPECT_EQ(slurp(other), "old");
  qsp::write_file_atomic(dest.string(), "destination", false);
  fs::create_symlink(dest, link);
  qsp::write_file_atomic(link.string(), "through", true);
  EXPECT_FALSE(fs::is_symlink(link));
  EXPECT_EQ(slurp(link), "through");
  EXPECT_EQ(slurp(dest), "destination");
  // Relative path in the current directory.
  const fs::path cwd = fs::current_path();
  fs::current_path(dir.path());
  qsp::write_file_atomic("rel.off", "rel", false);
  fs::current_path(cwd);
  EXPECT_EQ(slurp(dir.path() / "rel.off"), "rel");
  // No temporary files left behind.
  for (const auto& e : fs::directory_iterator(dir.path())) {
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
  }
}

TEST(Files, AtomicWriteFailuresAreIoErrorsAndLeaveNothing) {
  TempDir dir;
  const std::string no_dir = (dir.path() / "no" / "such" / "dir" / "x.obj").string();
  std::string msg = expect_error([&] { qsp::write_file_atomic(no_dir, "x", false); }, qsp::ErrorCode::kIo);
  EXPECT_NE(msg.find(no_dir + ": cannot create a temporary file"), std::string::npos) << msg;
  EXPECT_NE(msg.find("No such file or directory"), std::string::npos) << msg;

  spit(dir.path() / "plain", "not a directory");
  const std::string under_file = (dir.path() / "plain" / "x.obj").string();
  msg = expect_error([&] { qsp::write_file_atomic(under_file, "x", true); }, qsp::ErrorCode::kIo);
  EXPECT_NE(msg.find("Not a directory"), std::string::npos) << msg;

  // Target is a directory: rename cannot replace it; the temporary file must be gone.
  fs::create_directory(dir.path() / "adir");
  msg = expect_error([&] { qsp::write_file_atomic((dir.path() / "adir").string(), "x", true); },
                     qsp::ErrorCode::kIo);
  EXPECT_EQ(msg.rfind((dir.path() / "adir").string() + ": ", 0), 0u) << msg;
  for (const auto& e : fs::directory_iterator(dir.path())) {
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
  }
}

TEST(Files, DeviceTargetIsWrittenInPlace) {
  if (!fs::exists("/dev/null")) GTEST_SKIP();
  qsp::write_file_atomic("/dev/null", "discarded", true);
  EXPECT_TRUE(fs::is_character_file("/dev/null"));  // not replaced by a regular file
  expect_error([] { qsp::write_file_atomic("/dev/null", "x", false); }, qsp::ErrorCode::kIo);
  if (fs::exists("/dev/full")) {
    const std::string msg =
        expect_error([] { qsp::write_file_atomic("/dev/full", "x", true); }, qsp::ErrorCode::kIo);
    EXPECT_NE(msg.find("No space left on device"), std::string::npos) << msg;
  }
}

TEST(Files, StdoutWriteToFullDeviceFails) {
  const int full = ::open("/dev/full", O_WRONLY | O_CLOEXEC);
  if (full < 0) GTEST_SKIP() << "/dev/full not available";
  std::fflush(stdout);
  const int saved = ::dup(STDOUT_FILENO);
  ASSERT_GE(saved, 0);
  ::dup2(full, STDOUT_FILENO);
  std::string msg;
  try {
    qsp::write_file_atomic("-", "data that cannot be written", false);
  } catch (const qsp::Error& e) {
    msg = e.what();
    EXPECT_EQ(e.code(), qsp::ErrorCode::kIo);
  }
  ::dup2(saved, STDOUT_FILENO);
  ::close(saved);
  ::close(full);
  EXPECT_NE(msg.find("-: cannot write standard output: No space left on device"), std::string::npos) << msg;
}

TEST(Files, ReadMeshFileRoundTripThroughDisk) {
  std::mt19937 rng(99);
  const qsp::QuadMesh m = random_mesh(rng, 300, 200);
  TempDir dir;
  qsp::write_file_atomic((dir.path() / "m.obj").string(), qsp::write_obj(m), false);
  qsp::write_file_atomic((dir.path() / "m.off").string(), qsp::write_off(m), false);
  expect_bit_exact(m, qsp::read_mesh_file((dir.path() / "m.obj").string()));
  expect_bit_exact(m, qsp::read_mesh_file((dir.path() / "m.off").string()));
  qsp::ReadReport r;
  r.tags = 5;  // readers start from a clean report
  (void)qsp::read_mesh_file((dir.path() / "m.obj").string(), &r);
  EXPECT_EQ(r.tags, 0u);
  EXPECT_EQ(r.face_line.size(), 200u);
}

TEST(Files, StandardInputIsReadToEof) {
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  const std::string text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  ASSERT_EQ(::write(fds[1], text.data(), text.size()), static_cast<ssize_t>(text.size()));
  ::close(fds[1]);
  const int saved = ::dup(STDIN_FILENO);
  ::dup2(fds[0], STDIN_FILENO);
  ::close(fds[0]);
  qsp::QuadMesh m;
  std::string error;
  try {
    m = qsp::read_mesh_file("-", nullptr, qsp::MeshFormat::kObj);
  } catch (const std::exception& e) {
    error = e.what();
  }
  ::dup2(saved, STDIN_FILENO);
  ::close(saved);
  EXPECT_EQ(error, "");
  EXPECT_EQ(m.face_count(), 1u);
}
