// `qsp stats` end to end: Table-1 rows, JSON, and every invalid mesh refused with file:line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "qsp/canonical.h"
#include "qsp/codec.h"
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

// A .qsp row says what its level searched, in compress --help's words (issue 18: stats and --help say
// what each level does).
TEST(CliStats, QspRowSaysWhatItsLevelDoes) {
  const std::string golden = std::string(QSP_TESTDATA_DIR) + "/golden/";
  auto r = run_qsp("stats " + quote(golden + "tools/tilted_noise_q14_lcsm.qsp"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("  level 9: " + level_description(9) + "\n"), std::string::npos) << r.out;
  const std::string mesh = std::string(QSP_TESTDATA_DIR) + "/cube_4.obj";
  const fs::path out = fs::temp_directory_path() / ("qsp_stats_level_" + std::to_string(::getpid()) + ".qsp");
  ASSERT_EQ(run_qsp("compress -f -1 --quantize 12 " + quote(mesh) + " -o " + quote(out.string())).exit_code,
            0);
  r = run_qsp("stats " + quote(out.string()));
  fs::remove(out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("  level 1: " + level_description(1) + "\n"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("level 9:"), std::string::npos) << r.out;
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

// Reader defects and what is not a mesh: exit 1, message with the expected code's text and location.
// Faces that are not quads and non-manifold or mis-oriented quads are polygon meshes now (issue 20):
// stats reports them, below.
TEST(CliStats, EveryInvalidMeshIsRefusedWithItsLocation) {
  int n = 0, polygon = 0;
  for (const fs::path& mesh : testing::invalid_meshes()) {
    SCOPED_TRACE(mesh.string());
    const auto expect = testing::read_expect(fs::path(mesh).replace_extension(".expect"));
    ASSERT_TRUE(expect.count("message")) << "missing .expect";
    const auto r = run_qsp("stats " + quote(mesh.string()));
    const std::string& code = expect.at("code");
    if (code == "non-manifold" || code == "orientation" || (code == "not-quad" && r.exit_code == 0)) {
      EXPECT_EQ(r.exit_code, 0) << r.err;
      EXPECT_NE(r.out.find("  polygons: "), std::string::npos) << r.out;
      ++polygon;
      continue;
    }
    EXPECT_EQ(r.exit_code, code == "io" ? 3 : 1) << r.err;  // README's exit codes
    // A file with a face of two vertices is no polygon mesh either: the polygon reader says so.
    const std::string message =
        code == "not-quad" ? "a face needs at least 3 distinct vertices" : expect.at("message");
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
    ++n;
  }
  EXPECT_GT(n, 40);
  EXPECT_GE(polygon, 6);
}

// The shared polygon meshes: the quad submesh's row and the face counts; what is not a mesh (a face
// repeating a vertex) is refused as before, naming the file and line.
TEST(CliStats, SharedPolygonMeshesAreReported) {
  QSP_NEEDS_SHARED();
  const fs::path dir = testing::shared_dir() / "meshes";
  for (const char* name : {"osd_catmark_nonquads.obj", "osd_catmark_bishop.obj",
                           "keenan_spot_control_mesh.obj", "pmp_suzanne.obj"}) {
    const auto r = run_qsp("stats " + quote((dir / name).string()));
    EXPECT_EQ(r.exit_code, 0) << name << r.err;
    EXPECT_NE(r.out.find("  polygons: "), std::string::npos) << r.out;
  }
  const auto r = run_qsp("stats " + quote((dir / "pmp_suzanne.obj").string()));
  EXPECT_NE(r.out.find("polygons: 468 quads, 32 triangles, 0 n-gons; 0 cut vertices"), std::string::npos)
      << r.out;
  for (const char* name : {"osd_catmark_nonman_edges.obj", "osd_catmark_nonman_quadpole64.obj"}) {
    const auto bad = run_qsp("stats " + quote((dir / name).string()));
    EXPECT_EQ(bad.exit_code, 1) << name << bad.err;
    EXPECT_NE(bad.err.find(std::string(name) + ":"), std::string::npos) << bad.err;  // says where
    EXPECT_NE(bad.err.find("face repeats vertex"), std::string::npos) << bad.err;
  }
}

// A hand-checked polygon mesh: a 3x3 grid whose middle cell is two triangles and whose corner cell a
// pentagon. Vertex (2,2) has quads on two sides, between them the triangles and the pentagon: its
// quads form two fans, so it is cut (one cut vertex, one extra copy). The row is the quad submesh's: 7
// quads on 16 vertices (16 + the copy - the pentagon's own vertex, which no quad has). A bow tie (two quads
// sharing one vertex) has one cut vertex. --json carries the same counts; an all-quad mesh's output has no
// polygon line or field.
TEST(CliStats, PolygonCountsBesideTheQuadSubmeshRow) {
  const std::string dir = ::testing::TempDir() + "qsp_stats_polygons_" + std::to_string(::getpid());
  fs::create_directories(dir);
  const std::string grid = dir + "/grid.obj", bowtie = dir + "/bowtie.obj";
  std::string obj;
  for (int y = 0; y <= 3; ++y)
    for (int x = 0; x <= 3; ++x) obj += "v " + std::to_string(x) + " " + std::to_string(y) + " 0\n";
  auto id = [](int x, int y) { return std::to_string(y * 4 + x + 1); };
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      if (i == 1 && j == 1) {
        obj += "f " + id(1, 1) + " " + id(2, 1) + " " + id(1, 2) + "\n";
        obj += "f " + id(2, 1) + " " + id(2, 2) + " " + id(1, 2) + "\n";
      } else if (i == 2 && j == 2) {
        obj += "v 2.5 3 0\nf " + id(2, 2) + " " + id(3, 2) + " " + id(3, 3) + " 17 " + id(2, 3) + "\n";
      } else {
        obj += "f " + id(i, j) + " " + id(i + 1, j) + " " + id(i + 1, j + 1) + " " + id(i, j + 1) + "\n";
      }
    }
  testing::spit(grid, obj);
  auto r = run_qsp("stats " + quote(grid));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(
      r.out.find("polygons: 7 quads, 2 triangles, 1 n-gons; 1 cut vertices (0 cut edges, 1 extra copies)"),
      std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("grid.obj        16        22         7 "), std::string::npos) << r.out;
  r = run_qsp("stats --json " + quote(grid));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"polygons\": {\"quads\": 7, \"triangles\": 2, \"ngons\": 1, \"cut_vertices\": 1, "
                       "\"cut_edges\": 0, \"extra_copies\": 1, \"vertices\": 17}"),
            std::string::npos)
      << r.out;
  testing::spit(bowtie,
                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 1 0\nv 2 2 0\nv 1 2 0\nf 1 2 3 4\nf 3 5 6 7\n");
  r = run_qsp("stats " + quote(bowtie));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(
      r.out.find("polygons: 2 quads, 0 triangles, 0 n-gons; 1 cut vertices (0 cut edges, 1 extra copies)"),
      std::string::npos)
      << r.out;
  // --sizes compresses it as compress does: the same bytes as the file compress writes, with the
  // polygons section's parts, and the stored row of that file says the same.
  const std::string qsp_file = dir + "/grid.qsp";
  ASSERT_EQ(run_qsp("compress -f " + quote(grid) + " " + quote(qsp_file)).exit_code, 0);
  const std::uint64_t file_size = fs::file_size(qsp_file);
  for (const std::string& args : {"--sizes " + quote(grid), quote(qsp_file)}) {
    SCOPED_TRACE(args);
    r = run_qsp("stats --json " + args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("\"bytes\": {\"total\": " + std::to_string(file_size) + ","), std::string::npos)
        << r.out;
    const std::size_t at = r.out.find("\"polygons_section\": {\"connectivity\": ");
    ASSERT_NE(at, std::string::npos) << r.out;
    unsigned conn = 0, positions = 0, in_geometry = 0;
    double bits = 0;
    ASSERT_EQ(
        std::sscanf(r.out.c_str() + at,
                    "\"polygons_section\": {\"connectivity\": %u, \"positions\": %u, "
                    "\"connectivity_bits_per_non_quad_face\": %lf, \"interior_positions_in_geometry\": %u",
                    &conn, &positions, &bits, &in_geometry),
        4)
        << r.out;
    EXPECT_GT(conn, 4u);  // four counts and a stream
    // The pentagon's vertex 17 and the grid's corner (3,3) are in no quad: the geometry section codes
    // their positions (3.12).
    EXPECT_EQ(positions, 0u);
    EXPECT_EQ(in_geometry, 2u) << "the pentagon's vertex 17 and corner (3,3) are in no quad";
    EXPECT_NEAR(bits, 8.0 * conn / 3, 1e-3) << "three faces are not quads";
    EXPECT_NE(r.out.find("\"format\": \"3.12\""), std::string::npos) << r.out;
    // Bits per vertex over the mesh's 17 vertices, not the quad submesh's 16.
    const std::size_t c = r.out.find("\"connectivity\": ", r.out.find("\"bytes\": {")),
                      b = r.out.find("\"bits_per_vertex\": ");
    ASSERT_TRUE(c != std::string::npos && b != std::string::npos) << r.out;
    unsigned long long conn_bytes = 0;
    double total = 0, conn_bits = 0;
    ASSERT_EQ(std::sscanf(r.out.c_str() + c, "\"connectivity\": %llu", &conn_bytes), 1) << r.out;
    ASSERT_EQ(std::sscanf(r.out.c_str() + b, "\"bits_per_vertex\": {\"total\": %lf, \"connectivity\": %lf",
                          &total, &conn_bits),
              2)
        << r.out;
    EXPECT_NEAR(total, 8.0 * file_size / 17, 1e-3) << r.out;
    EXPECT_NEAR(conn_bits, 8.0 * conn_bytes / 17, 1e-3) << r.out;
  }
  r = run_qsp("stats " + quote(qsp_file));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("[stored]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("polygons: 7 quads, 2 triangles, 1 n-gons"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("; 17 vertices in all"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("bits per non-quad face"), std::string::npos) << r.out;
  // --partition all: the three partitions' rows and the auto row, each with the counts.
  r = run_qsp("stats --partition all " + quote(grid));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* mode : {"[greedy]", "[merge]", "[auto]"})
    EXPECT_NE(r.out.find(mode), std::string::npos) << r.out;
  std::size_t counted = 0;
  for (std::size_t at = r.out.find("polygons: 7 quads"); at != std::string::npos;
       at = r.out.find("polygons: 7 quads", at + 1))
    ++counted;
  EXPECT_EQ(counted, 4u) << r.out;
  r = run_qsp("stats --json " + quote(std::string(QSP_TESTDATA_DIR) + "/cube_4.obj"));
  EXPECT_EQ(r.out.find("polygons"), std::string::npos) << r.out;
  fs::remove_all(dir);
}

TEST(CliStats, MissingFileAndUsage) {
  EXPECT_EQ(run_qsp("stats /nonexistent/x.obj").exit_code, 3);
  EXPECT_EQ(run_qsp("stats").exit_code, 2);
  EXPECT_EQ(run_qsp("frobnicate").exit_code, 2);
  const auto v = run_qsp("--version");
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_NE(v.out.find("qsp"), std::string::npos);
  const std::string now = "3." + std::to_string(kFormatMinor);
  EXPECT_NE(v.out.find("writes .qsp format " + now +
                       ", 3.0 for manifold quad meshes without a mirror; reads 3.0 to " + now),
            std::string::npos)
      << v.out;
}

}  // namespace
}  // namespace qsp
