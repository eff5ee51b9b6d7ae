// `qsp stats` end to end: Table-1 rows, JSON, and every invalid mesh refused with file:line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "qsp/canonical.h"
#include "qsp/io.h"
#include "qsp/partition.h"
#include "support/cli.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::run_qsp;

std::map<std::string, std::string> read_expect(const fs::path& p) {
  std::ifstream f(p);
  std::map<std::string, std::string> kv;
  for (std::string line; std::getline(f, line);) {
    const auto eq = line.find('=');
    if (eq != std::string::npos) kv[line.substr(0, eq)] = line.substr(eq + 1);
  }
  return kv;
}

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

// Reader and topology defects alike: exit 1, message with the expected code's text and location.
TEST(CliStats, EveryInvalidMeshIsRefusedWithItsLocation) {
  int n = 0;
  for (const auto& dir :
       {fs::path(QSP_TESTDATA_DIR) / "invalid", fs::path(QSP_TESTDATA_DIR) / "invalid" / "topology"}) {
    for (const auto& e : fs::directory_iterator(dir)) {
      const auto ext = e.path().extension();
      if (ext != ".obj" && ext != ".off" && ext != ".ply") continue;
      SCOPED_TRACE(e.path().string());
      const auto expect = read_expect(fs::path(e.path()).replace_extension(".expect"));
      ASSERT_TRUE(expect.count("message")) << "missing .expect";
      const auto r = run_qsp("stats " + quote(e.path().string()));
      EXPECT_EQ(r.exit_code, expect.at("code") == "limit" || expect.at("code") == "io" ? r.exit_code : 1);
      EXPECT_NE(r.exit_code, 0);
      EXPECT_NE(r.err.find(expect.at("message")), std::string::npos) << r.err;
      EXPECT_EQ(r.out, "");
      ++n;
    }
  }
  EXPECT_GT(n, 40);
}

TEST(CliStats, SharedInvalidCorpusIsRefusedClearly) {
  const fs::path dir = fs::path(QSP_SHARED_DIR) / "meshes";
  if (!fs::exists(dir)) GTEST_SKIP();
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
}

}  // namespace
}  // namespace qsp
