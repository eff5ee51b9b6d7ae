// OpenSubdiv tags (format 3.4, the subdivision tags section): crease, corner and hole follow the
// renumbering and name the same vertices and faces; a tag qsp cannot renumber keeps the original order;
// every prefix, bit flip and cut of a file is refused or decodes to tags in range. (Every shared OBJ's
// tags through the tool, read back by the test's own parser: SharedMeshesCli in test_hostile.cpp.)
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/polymesh.h"
#include "support/cli.h"
#include "support/corpus.h"
#include "support/files.h"
#include "support/polygon.h"
#include "support/section_sweep.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;

const std::string kTags = std::string(QSP_TESTDATA_DIR) + "/golden/tags/";

// Canonical: renumbered copies give the same bytes, and the decoded tags name the vertices and faces at
// the same positions; with keep_order they come back index for index.
TEST(Tags, RenumberedCopiesGiveTheSameBytesAndTheSameVertices) {
  std::vector<fs::path> files = {kTags + "cube_tags.obj"};
  for (const char* name : {"catmark_cube_creases1.obj", "catmark_torus_creases0.obj",
                           "catmark_hole_test1.obj", "catmark_bishop.obj"})
    if (fs::exists(testing::shared_dir() / "meshes/osd_shapes" / name))
      files.push_back(testing::shared_dir() / "meshes/osd_shapes" / name);
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    const PolygonMesh m = testing::read_obj_polygons(f);
    ASSERT_FALSE(m.tags.empty());
    for (int level : {1, 9}) {
      EncodeOptions o;
      o.level = level;
      const std::string bytes = encode_polygons(m, o);
      EXPECT_EQ(encode_polygons(testing::renumbered(m, 5), o), bytes);
      EXPECT_GE(static_cast<int>(bytes[9]), 4) << "a file with tags says format 3.4 (3.5 with normals)";
      EXPECT_EQ(testing::tags_by_position(decode_polygons(bytes)), testing::tags_by_position(m));
      o.keep_order = true;
      const PolygonMesh back = decode_polygons(encode_polygons(m, o));
      ASSERT_EQ(back.tags.size(), m.tags.size());
      for (std::size_t t = 0; t < m.tags.size(); ++t) {
        EXPECT_EQ(back.tags[t].ints, m.tags[t].ints);
        EXPECT_EQ(back.tags[t].floats, m.tags[t].floats);
        EXPECT_EQ(back.tags[t].strings, m.tags[t].strings);
      }
    }
  }
}

// A tag whose integers qsp cannot renumber is a usage error without keep_order (the tool then keeps the
// order and says so); bad tags are refused before a byte is written.
TEST(Tags, WhatCannotBeStoredIsRefused) {
  PolygonMesh m = testing::read_obj_polygons(kTags + "edit_keep_order.obj");
  EXPECT_THROW(encode_polygons(m), Error);
  EncodeOptions keep;
  keep.keep_order = true;
  EXPECT_EQ(decode_polygons(encode_polygons(m, keep)).tags.front().name, "vertexedit");
  for (int c = 0; c < 4; ++c) {
    PolygonMesh bad = testing::read_obj_polygons(kTags + "cube_tags.obj");
    SubdivisionTag& t = bad.tags[1];  // crease 4/2/0
    if (c == 0) t.ints.push_back(1);  // an odd crease
    if (c == 1) t.ints[0] = 8;        // past the vertices
    if (c == 2) t.name = "two words";
    if (c == 3) t.floats[0] = 0.1;  // binary32 does not hold it
    try {
      (void)encode_polygons(bad);
      ADD_FAILURE() << "case " << c << " encoded";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kUsage) << e.what();
      EXPECT_NE(std::string(e.what()).find("tag 1 ('"), std::string::npos) << e.what();
    }
  }
}

TEST(Tags, EveryPrefixBitFlipAndCutIsSafe) {
  for (const char* name : {"cube_tags", "cube_tags_keep_order", "edit_keep_order"}) {
    SCOPED_TRACE(name);
    const std::string good = testing::slurp(kTags + name + ".qsp");
    const int decoded = testing::sweep_section(good, container::kTagTags, 4, [](const PolygonMesh& got) {
      for (const SubdivisionTag& t : got.tags) {
        const std::size_t limit = t.name == "hole" ? got.face_count() : got.vertex_count();
        if (t.name == "crease" || t.name == "corner" || t.name == "hole") {
          for (const std::int64_t i : t.ints) ASSERT_TRUE(i >= 0 && static_cast<std::size_t>(i) < limit);
        }
        ASSERT_FALSE(t.name.empty());
      }
    });
    EXPECT_GT(decoded, 0) << "some flips change an integer or a float and still decode";
  }
}

// The OBJ writer puts faces without a material first when one follows faces with one (OBJ cannot take
// it away): a hole then names the face where it is written.
TEST(Tags, AHoleFollowsItsFaceWhenTheWriterMovesIt) {
  Mesh m = read_obj_mesh(
      "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n"
      "usemtl red\nf 1 2 5 4\nf 2 3 6 5\nt hole 1/0/0 1\n",
      "in.obj");
  m.materials.face = {0, kInvalid};  // face 1 lost its material: it must be written first
  m.statements.clear();
  const Mesh back = read_obj_mesh(write_obj_mesh(m), "out.obj");
  ASSERT_EQ(back.tags.size(), 1u);
  const std::int64_t hole = back.tags[0].ints.at(0);
  EXPECT_EQ(hole, 0) << "the face without a material comes first";
  EXPECT_EQ(back.materials.face.at(static_cast<std::size_t>(hole)), kInvalid);
  EXPECT_EQ(back.corner_vertices.at(back.face_offsets[static_cast<std::size_t>(hole)]), 1u);
}

class TagsCli : public testing::TempDirTest {};

TEST_F(TagsCli, KeptWrittenBackAndSaidWhenTheOrderIsKeptForThem) {
  auto r = testing::run_qsp("compress " + testing::quote(kTags + "edit_keep_order.obj") + " " +
                            testing::quote(p("e.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("keeping the original order (as --keep-order): tag 'vertexedit'"), std::string::npos)
      << r.err;
  EXPECT_TRUE(inspect(testing::slurp(p("e.qsp"))).keep_order);
  r = testing::run_qsp("decompress " + testing::quote(p("e.qsp")) + " " + testing::quote(p("e.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(testing::slurp(p("e.obj")).find("t vertexedit 7/3/2 2 0 3 1 0 2 1 0.5 0.25 -1 value set\n"),
            std::string::npos);
  r = testing::run_qsp("decompress " + testing::quote(p("e.qsp")) + " " + testing::quote(p("e.off")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("OFF cannot hold"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("subdivision tags (--drop tag)"), std::string::npos) << r.err;
  // A value of more digits than binary64 holds is refused by name, not rounded.
  testing::spit(p("d.obj"),
                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
                "t corner 1/1/0 0 0.123456789012345678901234567\n");
  r = testing::run_qsp("compress " + testing::quote(p("d.obj")) + " " + testing::quote(p("d.qsp")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("tag 0 ('corner') has a value of more digits than float64 holds"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(p("d.qsp")));
}

}  // namespace
}  // namespace qsp
