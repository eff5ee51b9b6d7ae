// Normals (format 3.5, the normals section, coded as texture coordinates are): every corner comes back
// with its normal bit for bit; renumbered copies give the same bytes; every prefix, bit flip and cut of
// a file is refused or decodes to normals in range. (Every shared OBJ's normals through the tool, read
// back by the test's own parser: SharedMeshesCli in test_hostile.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "support/corpus.h"
#include "support/files.h"
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
      EXPECT_EQ(static_cast<int>(bytes[9]), 5) << "a file with normals says format 3.5";
      EXPECT_EQ(encode_polygons(testing::renumbered(m, 11), o), bytes);
      o.quantize_bits = 12;  // the positions the coder predicts from are then the decoded ones
      EXPECT_EQ(encode_polygons(testing::renumbered(m, 12), o), encode_polygons(m, o));
      o.quantize_bits = 0;
      o.keep_order = true;
      const PolygonMesh back = decode_polygons(encode_polygons(m, o));
      EXPECT_EQ(back.corner_normals, m.corner_normals);
      EXPECT_EQ(back.normals, m.normals);
    }
  }
}

TEST(Normals, EveryPrefixBitFlipAndCutIsSafe) {
  for (const char* name : {"cube_normals", "grid_normals_keep_order"}) {
    SCOPED_TRACE(name);
    const std::string good = testing::slurp(kNormals + name + ".qsp");
    testing::sweep_section(good, container::kTagNormals, 5, [](const PolygonMesh& got) {
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
