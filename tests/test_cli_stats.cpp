// `qsp stats` end to end: Table-1 rows, JSON, and every invalid mesh refused with file:line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "qsp/canonical.h"
#include "qsp/io.h"
#include "qsp/partition.h"
#include "support/cli.h"
#include "support/corpus.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::run_qsp;

TEST(CliStats, TableRowMatchesLibrary) {
  const std::string mesh = std::string(QSP_TESTDATA_DIR) + "/cube_4.obj";
  const auto r = run_qsp("stats " + quote(mesh));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // 8 extraordinary vertices, 8 schematic vertices, 12 edges, 6 patches.
  EXPECT_NE(r.out.find("98"), std::string::npos) << r.out;  // V = 6*16 + 2 = 98
  EXPECT_NE(r.out.find("|       8      12       6 |"), std::string::npos) << r.out;
}

TEST(CliStats, JsonHasTheDocumentedFields) {
  const std::string a = std::string(QSP_TESTDATA_DIR) + "/cube_4.obj";
  const std::string b = std::string(QSP_TESTDATA_DIR) + "/multi_component.obj";
  const auto r = run_qsp("stats --json --verbose " + quote(a) + " " + quote(b));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.front(), '[');
  for (const char* key : {"\"file\"", "\"mesh\"", "\"vertices\": 98", "\"edges\": 192", "\"faces\": 96",
                          "\"components\": 4", "\"extraordinary\": 8", "\"schematic\"", "\"patches\": 6",
                          "\"unreferenced\": 1", "\"kind\": \"torus\""})
    EXPECT_NE(r.out.find(key), std::string::npos) << key << "\n" << r.out;
}

// A .qsp row says which format version and level wrote it, and how its geometry is coded: the order
// and the tools (testdata/golden/tools/ pins every combination).
TEST(CliStats, QspRowNamesItsFormatAndCoding) {
  const std::string golden = std::string(QSP_TESTDATA_DIR) + "/golden/";
  auto r = run_qsp("stats " + quote(golden + "tools/tilted_noise_q14_lcsm.qsp"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(
      r.out.find("format 3.0, level 9, geometry layout order, tools: normal chaining, cell shapes, logistic "
                 "mixing; quantized to 14 bits"),
      std::string::npos)
      << r.out;
  r = run_qsp("stats " + quote(golden + "tools/tilted_noise_r.qsp"));
  EXPECT_NE(r.out.find("geometry patch order, tools: value repeats; lossless"), std::string::npos) << r.out;
  r = run_qsp("stats " + quote(golden + "tools/tilted_noise_q14_plain.qsp"));
  EXPECT_NE(r.out.find("geometry patch order, tools: none;"), std::string::npos) << r.out;
  r = run_qsp("stats --json " + quote(golden + "tools/tilted_noise_q14_rc.qsp"));
  EXPECT_NE(r.out.find("\"format\": \"3.0\", \"level\": 9, \"geometry_coding\": {\"tools\": \"value repeats, "
                       "normal chaining\", \"order\": \"patch\"}"),
            std::string::npos)
      << r.out;
}

// `stats --partition auto` reports what `compress` writes: the same total bytes as the file.
TEST(CliStats, AutoRowMatchesTheCompressedFile) {
  const testing::TempDir dir;
  for (const char* name : {"keenan_spot_quadrangulated.obj", "l_shape.obj", "multi_component.obj"}) {
    SCOPED_TRACE(name);
    const std::string in = std::string(QSP_TESTDATA_DIR) + "/" + name;
    const fs::path out = dir.path() / "x.qsp";
    ASSERT_EQ(run_qsp("compress -f --positions-only " + quote(in) + " " + quote(out.string())).exit_code, 0);
    const auto r = run_qsp("stats --json --partition auto " + quote(in));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("\"partition\": \"auto\""), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\"total\": " + std::to_string(fs::file_size(out)) + ","), std::string::npos)
        << r.out;
  }
}

// Reader and topology defects alike: exit 1, message with the expected code's text and location.
TEST(CliStats, EveryInvalidMeshIsRefusedWithItsLocation) {
  int n = 0;
  for (const fs::path& mesh : testing::invalid_meshes()) {
    SCOPED_TRACE(mesh.string());
    const auto expect = testing::read_expect(fs::path(mesh).replace_extension(".expect"));
    ASSERT_TRUE(expect.count("message")) << "missing .expect";
    const auto r = run_qsp("stats " + quote(mesh.string()));
    EXPECT_EQ(r.exit_code, expect.at("code") == "io" ? 3 : 1) << r.err;  // README's exit codes
    EXPECT_NE(r.err.find(expect.at("message")), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
    ++n;
  }
  EXPECT_GT(n, 40);
}

TEST(CliStats, SharedInvalidCorpusIsRefusedClearly) {
  QSP_NEEDS_SHARED();
  const fs::path dir = testing::shared_dir() / "meshes";
  for (const char* name :
       {"osd_catmark_nonman_edges.obj", "osd_catmark_nonman_quadpole64.obj", "osd_catmark_nonquads.obj",
        "osd_catmark_bishop.obj", "keenan_spot_control_mesh.obj", "pmp_suzanne.obj"}) {
    const auto r = run_qsp("stats " + quote((dir / name).string()));
    EXPECT_EQ(r.exit_code, 1) << name << r.err;
    EXPECT_NE(r.err.find(std::string(name) + ":"), std::string::npos) << r.err;  // says where
  }
}

TEST(CliStats, MissingFileAndUsage) {
  EXPECT_EQ(run_qsp("stats /nonexistent/x.obj").exit_code, 3);
  EXPECT_EQ(run_qsp("stats").exit_code, 2);
  EXPECT_EQ(run_qsp("frobnicate").exit_code, 2);
  const auto v = run_qsp("--version");
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_NE(v.out.find("qsp"), std::string::npos);
  EXPECT_NE(v.out.find("writes .qsp format 3.1, 3.0 for manifold quad meshes; reads 3.0 to 3.1"),
            std::string::npos)
      << v.out;
}

}  // namespace
}  // namespace qsp
