// Texture coordinates (format 3.2, the texture coordinates section): every shared mesh with `vt` comes
// back with the same texture coordinate on every corner (compared by an independent parse of both
// OBJ texts), renumbered copies give the same bytes, and every prefix and bit flip of a file is
// refused or decodes without harm.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/submesh.h"
#include "support/cli.h"
#include "support/corpus.h"
#include "support/files.h"
#include "support/mesh_text.h"
#include "support/minor.h"
#include "support/polygon.h"
#include "support/section_sweep.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;

// Every shared OBJ with texture coordinates, keep-order round trip through the tool: the decompressed
// text names, face for face and corner for corner, the same position and texture coordinate values
// (as float32) as the input text, both read by the test's own parser.
TEST(Texcoords, SharedMeshesComeBackCornerForCorner) {
  QSP_NEEDS_SHARED();
  testing::TempDir dir;
  int with_uv = 0;
  for (const fs::path& f : testing::shared_meshes()) {
    if (f.extension() != ".obj") continue;
    const testing::TextMesh in = testing::parse_obj_text(testing::slurp(f.string()));
    if (in.texcoords.empty()) continue;
    SCOPED_TRACE(f.string());
    const std::string q = dir.p("m.qsp"), back = dir.p("back.obj");
    const auto r = testing::run_qsp(
        "compress -f -q --keep-order --drop normal,color,group,material,smoothing,tag,extra " +
        testing::quote(f.string()) + " " + testing::quote(q));
    if (r.exit_code != 0) {
      // Only what is not a mesh (a face repeating a vertex) is refused.
      EXPECT_NE(r.err.find("repeats vertex"), std::string::npos) << r.err;
      continue;
    }
    ++with_uv;
    // 3.2, or 3.11 where the file's statement order is kept too (its interleaved vt and f lines), or
    // 3.12 where the geometry section also codes vertices in no quad.
    const FileInfo info = inspect(testing::slurp(q));
    const bool statements = std::any_of(info.sections.begin(), info.sections.end(),
                                        [](const SectionInfo& s) { return s.tag == 0x83; });
    EXPECT_EQ(info.version_minor,
              testing::minor_of_file_with(testing::slurp(q), statements ? kFormatMinorStatements : 2));
    ASSERT_EQ(
        testing::run_qsp("decompress -f -q " + testing::quote(q) + " -o " + testing::quote(back)).exit_code,
        0);
    const testing::TextMesh out = testing::parse_obj_text(testing::slurp(back));
    ASSERT_EQ(out.faces, in.faces);
    ASSERT_EQ(out.face_texcoords.size(), in.face_texcoords.size());
    const auto value = [](const testing::TextMesh& m, long t, std::size_t k) {
      return k < m.texcoords[static_cast<std::size_t>(t)].size()
                 ? std::stof(m.texcoords[static_cast<std::size_t>(t)][k])
                 : 0.0f;
    };
    for (std::size_t i = 0; i < in.faces.size(); ++i) {
      for (std::size_t c = 0; c < in.faces[i].size(); ++c) {
        const long a = in.face_texcoords[i].empty() ? -1 : in.face_texcoords[i][c];
        const long b = out.face_texcoords[i].empty() ? -1 : out.face_texcoords[i][c];
        ASSERT_EQ(a < 0, b < 0) << "face " << i << " corner " << c;
        if (a < 0) continue;
        ASSERT_EQ(a, b) << "face " << i << " corner " << c << ": the texture coordinates' order is kept";
        for (std::size_t k = 0; k < 3; ++k) ASSERT_EQ(value(in, a, k), value(out, b, k)) << "face " << i;
      }
    }
    ASSERT_EQ(out.texcoords.size(), in.texcoords.size());
  }
  EXPECT_GE(with_uv, 50);
}

// --quantize-uv 12: every texture coordinate within half a step (2^-13, and the input text's own
// rounding to float32) of the input's, read back by the test's own parser face for face; a far-off
// value (a UV at 1e5, which stretches Draco's grid) changes no other value, which keep the step 2^-12.
TEST(Texcoords, QuantizedValuesAreWithinHalfAStepWhateverTheOutliers) {
  testing::TempDir dir;
  const std::string spot = testing::slurp(std::string(QSP_TESTDATA_DIR) + "/keenan_spot_quadrangulated.obj");
  const std::string with_outlier = spot + "vt 100000 5\n";
  std::vector<testing::TextMesh> outs;
  for (const std::string& text : {spot, with_outlier}) {
    testing::spit(dir.p("in.obj"), text);
    const auto r = testing::run_qsp("compress -f -q --keep-order --quantize-uv 12 " +
                                    testing::quote(dir.p("in.obj")) + " " + testing::quote(dir.p("in.qsp")));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_EQ(testing::run_qsp("decompress -f -q " + testing::quote(dir.p("in.qsp")) + " -o " +
                               testing::quote(dir.p("out.obj")))
                  .exit_code,
              0);
    const testing::TextMesh in = testing::parse_obj_text(text);
    outs.push_back(testing::parse_obj_text(testing::slurp(dir.p("out.obj"))));
    const testing::TextMesh& out = outs.back();
    ASSERT_EQ(out.face_texcoords, in.face_texcoords);
    ASSERT_EQ(out.texcoords.size(), in.texcoords.size());
    for (std::size_t t = 0; t < in.texcoords.size(); ++t)
      for (std::size_t k = 0; k < 2; ++k)
        ASSERT_LE(std::fabs(std::stod(out.texcoords[t][k]) - std::stod(in.texcoords[t][k])),
                  std::ldexp(1.0, -13) + 1e-6)
            << "texture coordinate " << t;
  }
  // OFF holds no texture coordinate per corner: refused, saying how to drop them, and nothing written.
  const auto off = testing::run_qsp("decompress -f " + testing::quote(dir.p("in.qsp")) + " -o " +
                                    testing::quote(dir.p("out.off")));
  EXPECT_EQ(off.exit_code, 1);
  EXPECT_NE(off.err.find("OFF cannot hold"), std::string::npos) << off.err;
  EXPECT_NE(off.err.find("texture coordinates per corner (seams) (--drop uv)"), std::string::npos) << off.err;
  EXPECT_FALSE(std::filesystem::exists(dir.p("out.off")));
  // The outlier came back exactly (it is on the grid) and changed nothing else.
  ASSERT_EQ(outs[1].texcoords.size(), outs[0].texcoords.size() + 1);
  EXPECT_EQ(std::stod(outs[1].texcoords.back()[0]), 100000.0);
  outs[1].texcoords.pop_back();
  EXPECT_EQ(outs[1].texcoords, outs[0].texcoords);
}

// A texture coordinate with more digits than float32 holds is kept exactly (format 3.13's exact values
// section) and written back as its text; --float32 rounds it and says so, --quantize-uv rounds it on its
// grid, --drop uv drops it.
TEST(Texcoords, ValuesFloat32DoesNotHoldAreKeptUnlessRounded) {
  testing::TempDir dir;
  testing::spit(dir.p("in.obj"),
                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0.1234567891\nvt 1 1\nvt 0 1\n"
                "f 1/1 2/2 3/3 4/4\n");
  const std::string in = testing::quote(dir.p("in.obj")), out = testing::quote(dir.p("in.qsp"));
  auto r = testing::run_qsp("compress " + in + " " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(testing::slurp(dir.p("in.qsp"))[9],
            testing::minor_of_file_with(testing::slurp(dir.p("in.qsp")), kFormatMinorExactValues));
  r = testing::run_qsp("decompress -f " + out + " -o " + testing::quote(dir.p("back.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(testing::slurp(dir.p("back.obj")).find("\nvt 1 0.1234567891\n"), std::string::npos)
      << testing::slurp(dir.p("back.obj"));
  r = testing::run_qsp("compress -f --quantize-uv 12 " + in + " " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(decode_polygons(testing::slurp(dir.p("in.qsp"))).texcoords64.empty());
  r = testing::run_qsp("compress -f --float32 " + in + " " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("rounded 1 texture coordinate values to float32 (--float32)"), std::string::npos)
      << r.err;
  EXPECT_EQ(decode_polygons(testing::slurp(dir.p("in.qsp"))).texcoords.size(), 8u);
  EXPECT_TRUE(decode_polygons(testing::slurp(dir.p("in.qsp"))).texcoords64.empty());
  r = testing::run_qsp("compress -f --drop uv " + in + " " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(decode_polygons(testing::slurp(dir.p("in.qsp"))).texcoord_components, 0);
}

// Canonical: renumbering vertices, faces and texture coordinates and rotating corners gives the same
// bytes; the decoded mesh has the input's corners with their texture coordinates.
TEST(Texcoords, RenumberedCopiesGiveTheSameBytes) {
  std::vector<fs::path> files = {fs::path(QSP_TESTDATA_DIR) / "golden/texcoords/grid_seam.obj",
                                 fs::path(QSP_TESTDATA_DIR) / "golden/texcoords/polygon_uv.obj"};
  for (const char* name : {"keenan_spot_quadrangulated.obj", "osd_catmark_bishop.obj", "mh_fedora.obj"})
    if (fs::exists(testing::shared_dir() / "meshes" / name))
      files.push_back(testing::shared_dir() / "meshes" / name);
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    const PolygonMesh m = testing::read_obj_polygons(f);
    ASSERT_GT(m.texcoord_components, 0);
    for (int level : {1, 9}) {
      EncodeOptions o;
      o.level = level;
      const std::string bytes = encode_polygons(m, o);
      EXPECT_EQ(encode_polygons(testing::renumbered(m, 7), o), bytes);
      o.quantize_bits = 12;  // the shapes then come from the decoded positions
      EXPECT_EQ(encode_polygons(testing::renumbered(m, 8), o), encode_polygons(m, o));
      o.quantize_texcoord_bits = 10;
      EXPECT_EQ(encode_polygons(testing::renumbered(m, 9), o), encode_polygons(m, o));
    }
  }
}

// Flag bit 7 (hints from the faces across, residuals by activity) is format 3.16's: the golden that has it
// says 3.16 (as written before 3.17's mirror prediction), and the same sections in a file saying 3.15 are
// refused, naming both versions and where.
TEST(Texcoords, HintsInAnOlderFileAreRefused) {
  const std::string good =
      testing::slurp(std::string(QSP_TESTDATA_DIR) + "/golden/v3.16/texcoords/cylinder_seam_uv12.qsp");
  const container::File f = container::parse(good);
  ASSERT_TRUE(static_cast<std::uint8_t>(f.find(container::kTagTexcoords)->payload[0]) & 0x80);
  EXPECT_EQ(good[9], kFormatMinorSeamHints);
  std::string sections;
  for (const container::Section& s : f.sections) container::put_section(sections, s.tag, s.payload);
  try {
    decode_polygons(container::seal(f.major, kFormatMinorSeamHints - 1, f.level, sections));
    ADD_FAILURE() << "decoded";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kFormat);
    EXPECT_NE(std::string(e.what()).find("format 3.16's, and the file says it is 3.15"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("byte offset"), std::string::npos) << e.what();
  }
}

// A reserved flag bit in a file of this qsp's minor version is a corrupt file; in a file of a newer minor
// version, which may have given it a meaning (as 3.16 did bit 7), it is a version error: upgrade qsp.
TEST(Texcoords, AReservedBitInANewerMinorSaysUpgrade) {
  const std::string good =
      testing::slurp(std::string(QSP_TESTDATA_DIR) + "/golden/texcoords/cylinder_seam_uv12.qsp");
  const container::File f = container::parse(good);
  std::string sections;
  for (const container::Section& s : f.sections) {
    std::string payload(s.payload);
    if (s.tag == container::kTagTexcoords) payload[0] = static_cast<char>(payload[0] | 0x40);
    container::put_section(sections, s.tag, payload);
  }
  for (const int minor : {int{kFormatMinor}, kFormatMinor + 1}) {
    SCOPED_TRACE(minor);
    try {
      decode_polygons(container::seal(f.major, static_cast<std::uint8_t>(minor), f.level, sections));
      ADD_FAILURE() << "decoded";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("reserved flag bits are set"), std::string::npos) << what;
      if (minor == kFormatMinor) {
        EXPECT_EQ(e.code(), ErrorCode::kFormat) << what;
      } else {
        EXPECT_EQ(e.code(), ErrorCode::kVersion) << what;
        EXPECT_NE(what.find("format 3." + std::to_string(kFormatMinor + 1) + ", newer than this qsp's 3." +
                            std::to_string(kFormatMinor)),
                  std::string::npos)
            << what;
        EXPECT_NE(what.find("upgrade qsp"), std::string::npos) << what;
      }
    }
  }
}

// Every prefix is refused; every single bit flip is refused or decodes to a mesh of the right size.
TEST(Texcoords, EveryPrefixAndBitFlipIsSafe) {
  for (const char* name :
       {"grid_seam", "grid_seam_keep_order", "polygon_uv", "cylinder_seam_uv12", "two_charts_uv12"}) {
    SCOPED_TRACE(name);
    const std::string good =
        testing::slurp(std::string(QSP_TESTDATA_DIR) + "/golden/texcoords/" + name + ".qsp");
    const PolygonMesh want = decode_polygons(good);
    EXPECT_EQ(want.corner_texcoords.size(), want.corners.size());
    testing::sweep_section(good, container::kTagTexcoords, 2, [](const PolygonMesh& got) {
      ASSERT_EQ(got.corner_texcoords.size(), got.corners.size());
      const std::size_t count = got.texcoords.size() / got.texcoord_components;
      for (const std::uint32_t t : got.corner_texcoords) ASSERT_TRUE(t == kInvalid || t < count);
      for (const float x : got.texcoords) ASSERT_TRUE(std::isfinite(x));
    });
  }
}

}  // namespace
}  // namespace qsp
