// Face labels (format 3.3, the face labels section): OBJ objects, groups, materials, smoothing groups
// and material libraries come back face for face; renumbered copies give the same bytes; every prefix,
// bit flip and cut of a file is refused or decodes to valid labels. (Every shared OBJ's labels, through
// the tool and read back by the test's own parser: SharedMeshesCli in test_hostile.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "bytes.h"
#include "codec_sections.h"
#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "support/cli.h"
#include "support/corpus.h"
#include "support/files.h"
#include "support/mesh_gen.h"
#include "support/polygon.h"
#include "support/section_sweep.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;

const std::string kLabels = std::string(QSP_TESTDATA_DIR) + "/golden/labels/";

// Per face, its labels by name ("-" for none), so two numberings of the names compare equal.
std::vector<std::string> named(const PolygonMesh& m) {
  std::vector<std::string> out(m.face_count());
  for (std::size_t f = 0; f < m.face_count(); ++f)
    for (const FaceLabels* l : {&m.objects, &m.groups, &m.materials, &m.smoothing})
      out[f] += (l->face.empty() || l->face[f] == kInvalid ? "-" : "'" + l->names[l->face[f]] + "'") + "|";
  return out;
}

// Canonical: renumbering vertices, faces and names and rotating corners gives the same bytes, at the
// fastest and the smallest level; with --keep-order the labels come back face for face.
TEST(Labels, RenumberedCopiesGiveTheSameBytes) {
  std::vector<fs::path> files = {kLabels + "grid_labels.obj", kLabels + "polygon_labels.obj"};
  for (const char* name : {"mh_base.obj", "osd_catmark_lefthanded.obj", "pmp_suzanne.obj"})
    if (fs::exists(testing::shared_dir() / "meshes" / name))
      files.push_back(testing::shared_dir() / "meshes" / name);
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    PolygonMesh m = testing::read_obj_polygons(f);
    ASSERT_TRUE(m.has_labels());
    for (int level : {1, 9}) {
      EncodeOptions o;
      o.level = level;
      const std::string bytes = encode_polygons(m, o);
      EXPECT_EQ(encode_polygons(testing::renumbered(m, 3), o), bytes);
      EXPECT_GE(static_cast<int>(bytes[9]), 3)
          << "a file with face labels says format 3.3 (or later: tags, normals)";
      o.keep_order = true;
      const PolygonMesh back = decode_polygons(encode_polygons(m, o));
      EXPECT_EQ(back.corners, m.corners);
      EXPECT_EQ(named(back), named(m));
      EXPECT_EQ(back.material_libraries, m.material_libraries);
    }
  }
}

// The canonical numbering of names: by the first output face that takes each, the ones no face takes
// last; a run of one label costs about nothing.
TEST(Labels, NamesAreNumberedByFirstUseAndRunsAreCheap) {
  PolygonMesh m = polygon_mesh(testing::grid(30, 30));
  const std::size_t nf = m.face_count();
  m.groups.names = {"unused", "b", "a"};
  m.groups.face.assign(nf, 2);
  m.groups.face[nf - 1] = 1;
  std::vector<std::uint32_t> identity(nf);
  for (std::uint32_t f = 0; f < nf; ++f) identity[f] = f;
  const std::string payload = encode_labels_section(m, identity);
  const DecodedLabels d = decode_labels_section(payload, 0, static_cast<std::uint32_t>(nf));
  EXPECT_EQ(d.groups.names, (std::vector<std::string>{"a", "b", "unused"}));
  EXPECT_EQ(d.groups.face.front(), 0u);
  EXPECT_EQ(d.groups.face.back(), 1u);
  EXPECT_LT(payload.size(), 1 + 1 + 2 + 2 + 2 + 2 + 7 + 12) << "names, and a few bytes for 900 faces";
  // A mesh's labels array of another length is a usage error, not a wrong file.
  m.groups.face.pop_back();
  EXPECT_THROW(encode_labels_section(m, identity), Error);
}

// A name or library with a line break would become a statement of its own: refused both ways.
TEST(Labels, LineBreaksInNamesAreRefused) {
  PolygonMesh m = polygon_mesh(testing::grid(1, 1));
  m.materials.names = {"red\nf 1 2 3"};
  m.materials.face = {0};
  try {
    (void)encode_polygons(m);
    ADD_FAILURE() << "encoded a name with a line break";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUsage);
    EXPECT_NE(std::string(e.what()).find("line break"), std::string::npos) << e.what();
  }
  const std::string bad = std::string("\x04\x01\x03", 3) + "a\rb";  // kinds: materials; one name "a\rb"
  try {
    (void)decode_labels_section(bad, 100, 1);
    ADD_FAILURE() << "decoded a name with a line break";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kFormat);
    EXPECT_NE(std::string(e.what()).find("byte offset 102"), std::string::npos) << e.what();
  }
}

// Names sharing prefixes are front-coded where that is smaller (format 3.9): the golden grid_prefixes
// says 3.9, and a front-coded section in a file that says it is older is refused.
TEST(Labels, FrontCodedNamesAreFormat39) {
  const std::string good = testing::slurp(kLabels + "grid_prefixes.qsp");
  EXPECT_EQ(static_cast<int>(good[9]), kFormatMinorNames);
  const container::File file = container::parse(good);
  const std::string payload(file.find(container::kTagLabels)->payload);
  EXPECT_EQ(labels_section_minor(payload), kFormatMinorNames);
  const auto faces = static_cast<std::uint32_t>(decode_polygons(good).face_count());
  EXPECT_EQ(decode_labels_section(payload, 0, faces, kFormatMinorNames).groups.names.size(), 12u);
  try {
    (void)decode_labels_section(payload, 0, faces, 8);
    FAIL() << "decoded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("front-coded names are format 3.9's, and the file says it is 3.8"),
              std::string::npos)
        << e.what();
  }
  // 5,001 names sharing 10,000 bytes cost 6 bytes each: past 64 text bytes a payload byte, refused
  // before the text is built.
  std::string hostile(1, '\x21');  // objects, front-coded
  const auto varint = [&hostile](std::uint64_t v) { put_varint(hostile, v); };
  varint(5001);
  varint(0), varint(10000), hostile += std::string(10000, 'x');
  for (int i = 0; i < 5000; ++i) {
    varint(10000), varint(3);
    hostile += {static_cast<char>('A' + i % 26), static_cast<char>('A' + i / 26 % 26),
                static_cast<char>('A' + i / 676)};
  }
  try {
    (void)decode_labels_section(hostile, 0, 1, kFormatMinorNames);
    FAIL() << "decoded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("names of more than 64 bytes a section byte"), std::string::npos)
        << e.what();
  }
  // The plainly coded goldens stay 3.3 files, byte for byte.
  EXPECT_EQ(static_cast<int>(testing::slurp(kLabels + "grid_labels.qsp")[9]), kFormatMinorLabels);
}

// Every prefix and bit flip is refused (the checksum); past it, every bit flip and cut of the section,
// the file resealed, is refused as a format error naming a byte offset or decodes to valid labels.
TEST(Labels, EveryPrefixBitFlipAndCutIsSafe) {
  for (const char* name : {"grid_labels", "grid_labels_keep_order", "polygon_labels", "grid_prefixes"}) {
    SCOPED_TRACE(name);
    const std::string good = testing::slurp(kLabels + name + ".qsp");
    const std::uint8_t minor = std::string(name) == "grid_prefixes" ? kFormatMinorNames : kFormatMinorLabels;
    const int decoded =
        testing::sweep_section(good, container::kTagLabels, minor, [](const PolygonMesh& got) {
          for (const FaceLabels* l : {&got.objects, &got.groups, &got.materials, &got.smoothing}) {
            ASSERT_TRUE(l->face.empty() || l->face.size() == got.face_count());
            for (const std::uint32_t n : l->face) ASSERT_TRUE(n == kInvalid || n < l->names.size());
          }
        });
    EXPECT_GT(decoded, 0) << "some flips change a name's text and still decode";
  }
}

// The tool: a labelled OBJ comes back with its labels; OFF, which cannot hold them, is refused by name.
class LabelsCli : public testing::TempDirTest {};

TEST_F(LabelsCli, DecompressWritesThemAndOffIsRefused) {
  const std::string in = kLabels + "grid_labels.obj", q = p("g.qsp");
  ASSERT_EQ(testing::run_qsp("compress -q " + testing::quote(in) + " " + testing::quote(q)).exit_code, 0);
  auto r = testing::run_qsp("decompress " + testing::quote(q) + " " + testing::quote(p("g.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = testing::slurp(p("g.obj"));
  for (const char* line : {"mtllib a.mtl b c.mtl\n", "o thing\n", "g right arm\n", "usemtl blue\n", "s off\n",
                           "g\n", "g unused\n"})
    EXPECT_NE(text.find(line), std::string::npos) << line;
  r = testing::run_qsp("decompress " + testing::quote(q) + " " + testing::quote(p("g.off")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("OFF cannot hold"), std::string::npos) << r.err;
  for (const char* drop : {"(--drop group)", "(--drop material)", "(--drop smoothing)"})
    EXPECT_NE(r.err.find(drop), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("g.off")));
}

}  // namespace
}  // namespace qsp
