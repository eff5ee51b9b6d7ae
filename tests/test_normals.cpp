// Normals (format 3.5, the normals section, coded as texture coordinates are; 3.10: predicted from the
// faces, octahedral): every corner comes back with its normal bit for bit (or within the octahedral
// grid's bound); renumbered copies give the same bytes; every prefix, bit flip and cut of a file is
// refused or decodes to normals in range. (Every shared OBJ's normals through the tool, read
// back by the test's own parser: SharedMeshesCli in test_hostile.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "support/corpus.h"
#include "support/files.h"
#include "support/minor.h"
#include "support/polygon.h"
#include "support/section_sweep.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;

const std::string kNormals = std::string(QSP_TESTDATA_DIR) + "/golden/normals/";

TEST(Normals, RenumberedCopiesGiveTheSameBytesAndKeepOrderGivesThemBack) {
  std::vector<fs::path> files = {kNormals + "cube_normals.obj", kNormals + "grid_normals_keep_order.obj"};
  for (const char* name :
       {"pmp_suzanne.obj", "osd_catmark_lefthanded.obj", "osd_shapes/catmark_chaikin0.obj"})
    if (fs::exists(testing::shared_dir() / "meshes" / name))
      files.push_back(testing::shared_dir() / "meshes" / name);
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    const PolygonMesh m = testing::read_obj_polygons(f);
    ASSERT_FALSE(m.corner_normals.empty());
    for (int level : {1, 9}) {
      EncodeOptions o;
      o.level = level;
      const std::string bytes = encode_polygons(m, o);
      EXPECT_TRUE(bytes[9] == testing::minor_of_file_with(bytes, 5) ||
                  bytes[9] == testing::minor_of_file_with(bytes, 10))
          << "a file with normals says format 3.5 or 3.10";
      EXPECT_EQ(encode_polygons(testing::renumbered(m, 11), o), bytes);
      o.quantize_bits = 12;  // the positions the coder predicts from are then the decoded ones
      EXPECT_EQ(encode_polygons(testing::renumbered(m, 12), o), encode_polygons(m, o));
      o.quantize_bits = 0;
      o.quantize_normal_bits = 10;
      EXPECT_EQ(encode_polygons(testing::renumbered(m, 13), o), encode_polygons(m, o));
      o.quantize_normal_bits = 0;
      o.keep_order = true;
      const PolygonMesh back = decode_polygons(encode_polygons(m, o));
      EXPECT_EQ(back.corner_normals, m.corner_normals);
      EXPECT_EQ(back.normals, m.normals);
    }
  }
}

// The flags byte of a file's normals section.
std::uint8_t normals_flags(const std::string& file) {
  const container::File f = container::parse(file);
  const container::Section* s = f.find(container::kTagNormals);
  return s && !s->payload.empty() ? static_cast<std::uint8_t>(s->payload[0]) : 0;
}

// The shared OBJ files with normals (empty without ../shared).
std::vector<fs::path> shared_with_normals() {
  std::vector<fs::path> out;
  for (const fs::path& f : testing::shared_meshes())
    if (f.extension() == ".obj" && testing::slurp(f).find("\nvn ") != std::string::npos) out.push_back(f);
  return out;
}

// The angle in radians between a and b (any length), well conditioned for small angles.
double angle(const float* a, const float* b) {
  const double x[3] = {a[0], a[1], a[2]}, y[3] = {b[0], b[1], b[2]};
  const double cross =
      std::hypot(x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]);
  return std::atan2(cross, x[0] * y[0] + x[1] * y[1] + x[2] * y[2]);
}

// The octahedral bound the spec states: 1.5 / h radians, h = 2^(bits-1) - 1, and binary32's rounding.
double octahedral_bound(std::uint32_t bits) { return 1.5 / double((1u << (bits - 1)) - 1) + 0x1p-23; }

bool has_zero_normal(const PolygonMesh& m) {
  for (std::size_t i = 0; i < m.normals.size(); i += 3)
    if (m.normals[i] == 0 && m.normals[i + 1] == 0 && m.normals[i + 2] == 0) return true;
  return false;
}

TEST(Normals, EveryCorpusMeshWithNormalsComesBackExactAndFaceNormalsPay) {
  QSP_NEEDS_SHARED();
  const std::vector<fs::path> files = shared_with_normals();
  ASSERT_GE(files.size(), 3u);
  int from_faces = 0;
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    const PolygonMesh m = testing::read_obj_polygons(f);
    EncodeOptions o;
    o.keep_order = true;
    const std::string bytes = encode_polygons(m, o);
    const PolygonMesh back = decode_polygons(bytes);
    EXPECT_EQ(back.corner_normals, m.corner_normals);
    ASSERT_EQ(back.normals.size(), m.normals.size());
    EXPECT_EQ(std::memcmp(back.normals.data(), m.normals.data(), 4 * m.normals.size()), 0);
    const bool faces = (normals_flags(bytes) & 0x20) != 0;
    EXPECT_EQ(bytes[9], testing::minor_of_file_with(bytes, faces ? 10 : 5))
        << "3.10 exactly when the normals are predicted from the faces";
    from_faces += faces;
  }
  // Suzanne's and OpenSubdiv's flat normals are their faces' normals.
  EXPECT_GE(from_faces, 3);
}

TEST(Normals, OctahedralNormalsAreWithinTheBound) {
  std::vector<PolygonMesh> meshes;
  for (const fs::path& f : shared_with_normals()) meshes.push_back(testing::read_obj_polygons(f));
  {
    // A bent grid whose corners each name a normal of their own in any direction, of any length.
    PolygonMesh g;
    const int n = 12;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> any(-1.0f, 1.0f);
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x)
        g.positions.insert(g.positions.end(), {float(x), float(y), float((x * y) % 5) * 0.25f});
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const auto v = static_cast<std::uint32_t>(y * (n + 1) + x);
        for (const std::uint32_t c : {v, v + 1, v + n + 2, v + n + 1}) {
          g.corners.push_back(c);
          g.corner_normals.push_back(static_cast<std::uint32_t>(g.normals.size() / 3));
          for (int k = 0; k < 3; ++k) g.normals.push_back(any(rng) * (k == 2 ? 3.0f : 1.0f));
        }
        g.face_offsets.push_back(static_cast<std::uint32_t>(g.corners.size()));
      }
    meshes.insert(meshes.begin(), g);
  }
  for (const PolygonMesh& m : meshes) {
    for (const std::uint32_t bits : {2u, 3u, 8u, 10u, 16u, 24u}) {
      SCOPED_TRACE(bits);
      EncodeOptions o;
      o.keep_order = true;
      o.quantize_normal_bits = bits;
      const std::string bytes = encode_polygons(m, o);
      const PolygonMesh back = decode_polygons(bytes);
      ASSERT_EQ(back.corner_normals, m.corner_normals);
      ASSERT_EQ(back.normals.size(), m.normals.size());
      if (has_zero_normal(m)) {  // kept exact
        EXPECT_FALSE(normals_flags(bytes) & 0x40);
        EXPECT_EQ(std::memcmp(back.normals.data(), m.normals.data(), 4 * m.normals.size()), 0);
        continue;
      }
      EXPECT_EQ(bytes[9], testing::minor_of_file_with(bytes, 10));
      EXPECT_TRUE(normals_flags(bytes) & 0x40) << "octahedral";
      double worst = 0;
      for (std::size_t i = 0; i < m.normals.size(); i += 3) {
        worst = std::max(worst, angle(&m.normals[i], &back.normals[i]));
        const double length =
            std::hypot(double{back.normals[i]}, double{back.normals[i + 1]}, double{back.normals[i + 2]});
        EXPECT_NEAR(length, 1.0, 1e-6);
      }
      EXPECT_LE(worst, octahedral_bound(bits));
      o.keep_order = false;
      EXPECT_TRUE(encode_polygons(testing::renumbered(m, 5), o) == encode_polygons(m, o)) << "canonical";
    }
  }
}

TEST(Normals, AZeroNormalKeepsThemExact) {
  PolygonMesh m = testing::read_obj_polygons(kNormals + "cube_normals.obj");
  m.normals[3] = m.normals[4] = m.normals[5] = 0.0f;
  EncodeOptions o;
  o.keep_order = true;
  o.quantize_normal_bits = 10;
  const std::string bytes = encode_polygons(m, o);
  EXPECT_FALSE(normals_flags(bytes) & 0x40);
  EXPECT_EQ(decode_polygons(bytes).normals, m.normals);
  o.quantize_normal_bits = 1;
  EXPECT_THROW(encode_polygons(m, o), Error);
  o.quantize_normal_bits = 25;
  EXPECT_THROW(encode_polygons(m, o), Error);
}

TEST(Normals, TheNewFlagsInAnOlderFileAreRefused) {
  for (const char* name : {"torus_normals", "torus_normals_qn10"}) {
    SCOPED_TRACE(name);
    // As written before 3.17 (its positions now use mirror prediction).
    const std::string good =
        testing::slurp(std::string(QSP_TESTDATA_DIR) + "/golden/v3.16/normals/" + name + ".qsp");
    ASSERT_EQ(good[9], 10);
    const container::File f = container::parse(good);
    std::string sections;
    for (const container::Section& s : f.sections) container::put_section(sections, s.tag, s.payload);
    const std::string older = container::seal(f.major, 9, f.level, sections);
    try {
      decode_polygons(older);
      ADD_FAILURE() << "decoded";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kFormat);
      EXPECT_NE(std::string(e.what()).find("format 3.10's, and the file says it is 3.9"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("byte offset"), std::string::npos) << e.what();
    }
    // Bit 7 stays reserved; bit 6 with bits 3 or 4 is not a file.
    const std::string payload(f.find(container::kTagNormals)->payload);
    for (const std::uint8_t bit : {0x80, 0x08, 0x10}) {
      std::string bad = payload;
      bad[0] = static_cast<char>(bad[0] | bit);
      if (bit != 0x80 && !(payload[0] & 0x40)) continue;
      EXPECT_THROW(decode_polygons(container::with_section(good, container::kTagNormals, bad, 10)), Error);
    }
  }
  // In a texture coordinates section bits 5 and 6 stay reserved.
  const std::string uv = testing::slurp(std::string(QSP_TESTDATA_DIR) + "/golden/texcoords/grid_seam.qsp");
  const container::File f = container::parse(uv);
  std::string bad(f.find(container::kTagTexcoords)->payload);
  bad[0] = static_cast<char>(bad[0] | 0x20);
  EXPECT_THROW(decode_polygons(container::with_section(uv, container::kTagTexcoords, bad, 10)), Error);
}

// Format 3.5's files (testdata/golden/v3.5/normals/: the goldens before normals were predicted from
// the faces) decode forever, to what today's files of the same meshes decode to.
TEST(Normals, FilesOfFormat35StillDecode) {
  for (const char* name : {"cube_normals", "grid_normals_keep_order"}) {
    SCOPED_TRACE(name);
    const std::string old =
        testing::slurp(std::string(QSP_TESTDATA_DIR) + "/golden/v3.5/normals/" + name + ".qsp");
    ASSERT_EQ(old[9], 5);
    const PolygonMesh was = decode_polygons(old),
                      is = decode_polygons(testing::slurp(kNormals + name + ".qsp"));
    EXPECT_EQ(was.corners, is.corners);
    EXPECT_EQ(was.positions, is.positions);
    EXPECT_EQ(was.corner_normals, is.corner_normals);
    EXPECT_EQ(std::memcmp(was.normals.data(), is.normals.data(), 4 * is.normals.size()), 0);
    ASSERT_EQ(was.normals.size(), is.normals.size());
  }
}

TEST(Normals, EveryPrefixBitFlipAndCutIsSafe) {
  for (const char* name :
       {"cube_normals", "grid_normals_keep_order", "torus_normals", "torus_normals_qn10"}) {
    SCOPED_TRACE(name);
    const std::string good = testing::slurp(kNormals + name + ".qsp");
    testing::sweep_section(good, container::kTagNormals, good[9], [](const PolygonMesh& got) {
      ASSERT_EQ(got.corner_normals.size(), got.corners.size());
      ASSERT_EQ(got.normals.size() % 3, 0u);
      for (const std::uint32_t n : got.corner_normals)
        ASSERT_TRUE(n == kInvalid || n < got.normals.size() / 3);
      for (const float x : got.normals) ASSERT_TRUE(std::isfinite(x));
    });
  }
}

}  // namespace
}  // namespace qsp
