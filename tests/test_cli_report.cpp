// What `qsp stats` says about a .qsp and what `qsp match` reports, end to end: lossless or quantized,
// order kept, bytes that add up, the same patch counts in every mode; mirror matches on request and a
// hint otherwise; isomorphism counts beyond 64 bits printed readably.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <regex>
#include <set>
#include <sstream>

#include "qsp/codec.h"
#include "qsp/io.h"
#include "support/cli.h"
#include "support/mesh_gen.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::run_qsp;
using testing::slurp;

const std::string kData = QSP_TESTDATA_DIR;

using CliReport = testing::TempDirTest;

// The numbers of "bytes: T total = H header + C connectivity (...) + G geometry (...)[ + O order][ + U
// texture coordinates]...[ + P properties][ + X other]".
std::vector<std::uint64_t> byte_parts(const std::string& out) {
  std::smatch m;
  static const std::regex re(
      R"(bytes: (\d+) total = (\d+) header \+ (\d+) connectivity \([^)]*\) \+ (\d+) geometry \([^)]*\)(?: \+ (\d+) order)?(?: \+ (\d+) texture coordinates)?(?: \+ (\d+) face labels)?(?: \+ (\d+) subdivision tags)?(?: \+ (\d+) normals)?(?: \+ (\d+) exact positions)?(?: \+ (\d+) colours)?(?: \+ (\d+) properties)?(?: \+ (\d+) comments)?(?: \+ (\d+) kept lines)?(?: \+ (\d+) other)?)");
  if (!std::regex_search(out, m, re)) return {};
  std::vector<std::uint64_t> v;
  for (int i = 1; i <= 15; ++i) v.push_back(m[i].matched ? std::stoull(m[i].str()) : 0);
  return v;
}

TEST_F(CliReport, StatsOnAQspSaysWhatItHoldsAndItsBytesAddUp) {
  const std::string mesh = kData + "/keenan_spot_quadrangulated.obj";
  struct Case {
    std::string options, says;
  };
  for (const Case& c :
       {Case{"", "lossless, canonical order"}, Case{"--quantize 12", "quantized to 12 bits, canonical order"},
        Case{"--quantize 14 --keep-order", "quantized to 14 bits, original order kept"},
        Case{"--keep-order --best", "format 3.17, level 9, geometry"}}) {  // Spot is symmetric
    SCOPED_TRACE(c.options);
    const std::string q = p("x.qsp");
    ASSERT_EQ(run_qsp("compress -f -q --positions-only " + c.options + " " + quote(mesh) + " " + quote(q))
                  .exit_code,
              0);
    auto r = run_qsp("stats " + quote(q));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find(c.says), std::string::npos) << r.out;
    const auto parts = byte_parts(r.out);
    ASSERT_EQ(parts.size(), 15u) << r.out;
    EXPECT_EQ(parts[0], fs::file_size(q));
    EXPECT_EQ(parts[0], std::accumulate(parts.begin() + 1, parts.end(), std::uint64_t{0})) << r.out;
    EXPECT_EQ(parts[4] > 0, c.options.find("--keep-order") != std::string::npos) << r.out;
    r = run_qsp("stats --json " + quote(q));
    const std::string bits =
        c.options.find("--quantize") == std::string::npos ? "0" : c.options.substr(11, 2);
    EXPECT_NE(r.out.find("\"quantize_bits\": " + bits + ","), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\"header\": " + std::to_string(parts[1]) + ", \"connectivity\": " +
                         std::to_string(parts[2]) + ", \"geometry\": " + std::to_string(parts[3]) +
                         ", \"order\": " + std::to_string(parts[4]) +
                         ", \"texcoords\": 0, \"labels\": 0, \"tags\": 0, \"normals\": 0, "
                         "\"exact_positions\": 0, \"colors\": 0, \"properties\": 0, \"comments\": 0, "
                         "\"kept_lines\": 0, \"other\": 0}"),
              std::string::npos)
        << r.out;
  }
}

// The leading comment block and the lines kept as text have parts of their own, by name, not "other";
// an OBJ's statement order (--keep-order, where the file needs one) is counted with the order.
TEST_F(CliReport, CommentsAndKeptLinesAreNamedInTheBytes) {
  testing::spit(p("c.obj"),
                "# licence line one\n# licence line two\nsome prose\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                "vt 0 0\nf 1/1 2/1 3/1 4/1\n");
  for (const char* options : {"", "--keep-order"}) {
    SCOPED_TRACE(options);
    ASSERT_EQ(
        run_qsp(std::string("compress -f -q ") + options + " " + quote(p("c.obj")) + " " + quote(p("c.qsp")))
            .exit_code,
        0);
    const auto r = run_qsp("stats " + quote(p("c.qsp")));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto parts = byte_parts(r.out);
    ASSERT_EQ(parts.size(), 15u) << r.out;
    EXPECT_EQ(parts[0], fs::file_size(p("c.qsp")));
    EXPECT_EQ(parts[0], std::accumulate(parts.begin() + 1, parts.end(), std::uint64_t{0})) << r.out;
    EXPECT_GT(parts[12], 0u) << r.out;
    EXPECT_GT(parts[13], 0u) << r.out;
    EXPECT_EQ(parts[14], 0u) << r.out;
    std::uint64_t comments = 0, kept = 0, statements = 0;
    for (const SectionInfo& si : inspect(slurp(p("c.qsp"))).sections) {
      if (si.tag == 0x81 || si.tag == 0x85) comments += si.size;
      if (si.tag == 0x82) kept += si.size;
      if (si.tag == 0x83) statements += si.size;
    }
    EXPECT_EQ(parts[12], comments);
    EXPECT_EQ(parts[13], kept);
    EXPECT_GE(parts[4], statements);
    EXPECT_EQ(parts[4] > 0, std::string(options) == "--keep-order") << r.out;
  }
}

// Every golden .qsp, of every format version: the parts add up to the file's size, and the precision is
// the one its name says (the *_q14 goldens are quantized to 14 bits, the others lossless).
TEST_F(CliReport, EveryGoldenFilesBytesAddUpAndNameItsPrecision) {
  int n = 0;
  for (const auto& e : fs::recursive_directory_iterator(kData + "/golden")) {
    if (e.path().extension() != ".qsp") continue;
    SCOPED_TRACE(e.path().string());
    const auto r = run_qsp("stats " + quote(e.path().string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    if (r.out.find("\n  polygons: ") != std::string::npos) {
      // A polygon file (3.1): stats shows its quad submesh's row and what the rest is, not yet its bytes.
      EXPECT_NE(r.out.find("the row is the quad submesh's"), std::string::npos) << r.out;
      ++n;
      continue;
    }
    const auto parts = byte_parts(r.out);
    ASSERT_EQ(parts.size(), 15u) << r.out;
    EXPECT_EQ(parts[0], fs::file_size(e.path()));
    // "other": sections the stats do not name (none in a golden).
    EXPECT_EQ(parts[14], 0u) << r.out;
    EXPECT_EQ(parts[0], std::accumulate(parts.begin() + 1, parts.end(), std::uint64_t{0})) << r.out;
    // Texture coordinates (3.2) and face labels (3.3) have their own parts (the statement order golden
    // has both).
    const bool statements = e.path().parent_path().filename() == "statements";
    EXPECT_EQ(parts[5] > 0, e.path().parent_path().filename() == "texcoords" ||
                                e.path().filename() == "grid_normals_keep_order.qsp" ||
                                e.path().filename() == "hull_uv12.qsp" || statements)
        << r.out;
    EXPECT_EQ(parts[6] > 0, e.path().parent_path().filename() == "labels" || statements) << r.out;
    EXPECT_EQ(parts[7] > 0, e.path().parent_path().filename() == "tags") << r.out;
    EXPECT_EQ(parts[8] > 0, e.path().parent_path().filename() == "normals") << r.out;
    EXPECT_EQ(parts[9] > 0, e.path().parent_path().filename() == "exact") << r.out;
    const bool q14 = e.path().filename().string().find("_q14") != std::string::npos;
    EXPECT_NE(r.out.find(q14 ? "; quantized to 14 bits, " : "; lossless, "), std::string::npos) << r.out;
    ++n;
  }
  EXPECT_GT(n, 40);
}

// A torus is one patch in every partition mode, in the stored row too; --partition on a .qsp decodes it
// and computes the rows asked for.
TEST_F(CliReport, CountsAgreeAcrossModesAndPartitionRecomputesOnAQsp) {
  const std::string mesh = kData + "/torus_twist_9x6_t2.obj";
  const std::string q = p("t.qsp");
  ASSERT_EQ(run_qsp("compress " + quote(mesh) + " " + quote(q)).exit_code, 0);
  auto r = run_qsp("stats --partition all " + quote(mesh) + " " + quote(q));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  int rows = 0;
  while (std::getline(lines, line)) {
    if (line.find(" | ") == std::string::npos || line.rfind("model", 0) == 0) continue;
    ++rows;
    EXPECT_NE(line.find("|       0       0       1 |"), std::string::npos) << line;
  }
  EXPECT_EQ(rows, 2 * 4 + 1) << r.out;  // mesh: 3 modes + auto; .qsp: stored + 3 modes + auto
  EXPECT_NE(r.out.find(q + " [stored]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(q + " [greedy]"), std::string::npos) << r.out;
  r = run_qsp("stats " + quote(q));
  EXPECT_EQ(r.out.find("[greedy]"), std::string::npos) << r.out;  // without --partition: the stored row only
}

// A flat L with arms of 6 and 3 cells: no mirror symmetry, so reversing its faces gives a mesh that is
// only isomorphic to it by an orientation-reversing map.
std::string chiral_obj(bool reversed) {
  std::string obj;
  for (int y = 0; y <= 4; ++y)
    for (int x = 0; x <= 6; ++x) obj += "v " + std::to_string(x) + " " + std::to_string(y) + " 0\n";
  const auto id = [](int x, int y) { return std::to_string(1 + y * 7 + x); };  // OBJ counts from 1
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) {
      if (!(y == 0 || x == 0)) continue;
      if (x == 0 && y == 3) continue;
      const std::string corners[4] = {id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)};
      obj += "f";
      for (int k = 0; k < 4; ++k) {
        obj += ' ';
        obj += corners[reversed ? (4 - k) % 4 : k];
      }
      obj += '\n';
    }
  return obj;
}

TEST_F(CliReport, MatchAcceptsMirrorsOnlyWhenAskedAndSaysWhichKind) {
  testing::spit(p("l.obj"), chiral_obj(false));
  testing::spit(p("l_flipped.obj"), chiral_obj(true));
  auto r =
      run_qsp("match " + quote(p("l.obj")) + " " + quote(p("l_flipped.obj")) + " -o " + quote(p("map.txt")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("not isomorphic"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(p("l_flipped.obj") + " is " + p("l.obj") + " with every face reversed"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("pass --allow-mirror"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(p("map.txt")));
  r = run_qsp("match --allow-mirror " + quote(p("l.obj")) + " " + quote(p("l_flipped.obj")) + " -o " +
              quote(p("map.txt")) + " --faces " + quote(p("faces.txt")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("isomorphic (orientation-reversing"), std::string::npos) << r.out;
  // The maps are a true orientation-reversing isomorphism: A's corner c of face f is vertex
  // map[A.quads[f][c]] = B.quads[G][(R - c) % 4].
  const QuadMesh a = read_mesh_file(p("l.obj")), b = read_mesh_file(p("l_flipped.obj"));
  std::istringstream vm(slurp(p("map.txt"))), fm(slurp(p("faces.txt")));
  std::vector<std::uint32_t> map(a.vertex_count());
  for (auto& v : map) vm >> v;
  for (std::size_t f = 0; f < a.face_count(); ++f) {
    std::uint32_t g = 0, rot = 0;
    ASSERT_TRUE(fm >> g >> rot);
    for (std::uint32_t c = 0; c < 4; ++c)
      EXPECT_EQ(map[a.quads[4 * f + c]], b.quads[4 * std::size_t(g) + ((rot + 4 - c) & 3u)]) << f << " " << c;
  }
  // An orientation-preserving match is still reported as such with the flag.
  r = run_qsp("match --allow-mirror " + quote(p("l.obj")) + " " + quote(p("l.obj")));
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out.find("orientation-reversing"), std::string::npos) << r.out;
}

// reorder takes --allow-mirror as match does: without it the refusal says why and how; with it OUT has
// REF's faces (and so REF's orientation) and IN's positions.
TEST_F(CliReport, ReorderHintsAndAcceptsMirrors) {
  testing::spit(p("l.obj"), chiral_obj(false));
  testing::spit(p("l_flipped.obj"), chiral_obj(true));
  auto r = run_qsp("reorder --like " + quote(p("l.obj")) + " " + quote(p("l_flipped.obj")) + " -o " +
                   quote(p("out.obj")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(p("l_flipped.obj") + " is " + p("l.obj") + " with every face reversed"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("pass --allow-mirror"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("out.obj")));
  r = run_qsp("reorder --allow-mirror --like " + quote(p("l.obj")) + " " + quote(p("l_flipped.obj")) +
              " -o " + quote(p("out.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("with every face reversed (--allow-mirror)"), std::string::npos) << r.err;
  const QuadMesh ref = read_mesh_file(p("l.obj")), in = read_mesh_file(p("l_flipped.obj")),
                 out = read_mesh_file(p("out.obj"));
  EXPECT_EQ(out.quads, ref.quads);
  std::multiset<std::array<float, 3>> want, got;  // IN's positions, all of them
  for (std::size_t v = 0; v < in.vertex_count(); ++v)
    want.insert({in.positions[3 * v], in.positions[3 * v + 1], in.positions[3 * v + 2]});
  for (std::size_t v = 0; v < out.vertex_count(); ++v)
    got.insert({out.positions[3 * v], out.positions[3 * v + 1], out.positions[3 * v + 2]});
  EXPECT_EQ(got, want);
}

// --prefer-order on a cube whose copy was turned in place, indices kept: the map is the identity (the
// report says none moved); without it the nearest isomorphism, which undoes the turn.
TEST_F(CliReport, PreferOrderKeepsTheIdentityOverANearerIsomorphism) {
  const QuadMesh cube = read_mesh_file(kData + "/cube_4.obj");
  QuadMesh turned = cube;
  for (std::size_t v = 0; v < cube.vertex_count(); ++v) {  // (x, y, z) -> (4 - y, x, z)
    turned.positions[3 * v] = 4.0f - cube.positions[3 * v + 1];
    turned.positions[3 * v + 1] = cube.positions[3 * v];
  }
  testing::spit(p("turned.obj"), write_obj(turned));
  const std::string args =
      quote(kData + "/cube_4.obj") + " " + quote(p("turned.obj")) + " -f -o " + quote(p("map.txt"));
  auto r = run_qsp("match --prefer-order " + args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("chose the one keeping most vertices at their index (0 moved), then the nearest"),
            std::string::npos)
      << r.out;
  std::istringstream map(slurp(p("map.txt")));
  std::uint32_t v = 0, i = 0, moved = 0;
  for (; map >> v; ++i) moved += v != i;
  EXPECT_EQ(i, cube.vertex_count());
  EXPECT_EQ(moved, 0u);
  r = run_qsp("match " + args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("chose the nearest, rms distance 0"), std::string::npos) << r.out;
  std::istringstream nearest(slurp(p("map.txt")));
  for (i = 0, moved = 0; nearest >> v; ++i) moved += v != i;
  EXPECT_GT(moved, 0u);
}

// A cube with every vertex at one point: all 24 isomorphisms are equally near. --prefer-order takes the
// identity, and the choice is then not ambiguous.
TEST_F(CliReport, PreferOrderKeepsTheIdentityAmongEquallyNearIsomorphisms) {
  const QuadMesh cube = read_mesh_file(kData + "/cube_4.obj");
  std::ostringstream obj;
  for (std::size_t v = 0; v < cube.vertex_count(); ++v) obj << "v 0 0 0\n";
  for (std::size_t f = 0; f < cube.face_count(); ++f)
    obj << "f " << 1 + cube.quads[4 * f] << " " << 1 + cube.quads[4 * f + 1] << " "
        << 1 + cube.quads[4 * f + 2] << " " << 1 + cube.quads[4 * f + 3] << "\n";
  testing::spit(p("point.obj"), obj.str());
  auto r = run_qsp("match " + quote(p("point.obj")) + " " + quote(p("point.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("ambiguous"), std::string::npos) << r.out;
  r = run_qsp("match --prefer-order " + quote(p("point.obj")) + " " + quote(p("point.obj")) + " -o " +
              quote(p("map.txt")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("ambiguous"), std::string::npos) << r.out;
  std::istringstream map(slurp(p("map.txt")));
  std::uint32_t v = 0, i = 0;
  for (; map >> v; ++i) EXPECT_EQ(v, i);
  EXPECT_EQ(i, cube.vertex_count());
  r = run_qsp("reorder --prefer-order --like " + quote(p("point.obj")) + " " + quote(p("point.obj")) +
              " -o " + quote(p("same.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");  // no "ambiguous" warning
  EXPECT_EQ(read_mesh_file(p("same.obj")).quads, cube.quads);
}

// 30 copies of a cube: 24^30 * 30! isomorphisms, about 2^245.3 -- not UINT64_MAX.
TEST_F(CliReport, HugeIsomorphismCountsArePrintedReadably) {
  testing::spit(p("cubes.obj"), write_obj(testing::copies(read_mesh_file(kData + "/cube_4.obj"), 30, 10.0f)));
  auto r = run_qsp("match " + quote(p("cubes.obj")) + " " + quote(p("cubes.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("about 2^245.3 (6.8e73) isomorphisms"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("18446744073709551615"), std::string::npos) << r.out;
  r = run_qsp("match " + quote(kData + "/cube_4.obj") + " " + quote(kData + "/cube_4.obj"));
  EXPECT_NE(r.out.find("isomorphic: 24 isomorphisms"), std::string::npos) << r.out;  // exact when it fits
}

// The file records the level that wrote it (header byte 10): stats shows it in the table and the JSON.
TEST_F(CliReport, StatsShowsTheLevelThatWroteAFile) {
  const std::string q = p("x.qsp");
  ASSERT_EQ(run_qsp("compress -q -7 " + quote(kData + "/cube_4.obj") + " " + quote(q)).exit_code, 0);
  auto r = run_qsp("stats --json " + quote(q));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"level\": 7,"), std::string::npos) << r.out;
  r = run_qsp("stats " + quote(q));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("level 7"), std::string::npos) << r.out;
  ASSERT_EQ(run_qsp("compress -q -f " + quote(kData + "/cube_4.obj") + " " + quote(q)).exit_code, 0);
  r = run_qsp("stats --json " + quote(q));
  EXPECT_NE(r.out.find("\"level\": " + std::to_string(kDefaultLevel) + ","), std::string::npos) << r.out;
}

}  // namespace
}  // namespace qsp
