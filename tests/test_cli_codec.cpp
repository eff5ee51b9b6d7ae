// qsp compress and decompress end to end: round trips, output rules, extra data, standard streams,
// corrupt files.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "support/cli.h"

namespace fs = std::filesystem;

namespace qsp {
namespace {

// ---- CLI ----

using testing::CliResult;
using testing::run_qsp;

// Each test's own folder, holding cube.obj (testdata/cube_4.obj).
class CliTest : public testing::TempDirTest {
 protected:
  void SetUp() override { fs::copy_file(std::string(QSP_TESTDATA_DIR) + "/cube_4.obj", dir_ / "cube.obj"); }
};

TEST_F(CliTest, CompressDecompressRoundTrip) {
  ASSERT_EQ(run_qsp("compress " + p("cube.obj")).exit_code, 0);
  ASSERT_TRUE(fs::exists(p("cube.obj.qsp")));
  // Default output would be cube.obj again: the input exists, so it is refused without -f.
  CliResult r = run_qsp("decompress " + p("cube.obj.qsp"));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("exists"), std::string::npos) << r.err;
  ASSERT_EQ(run_qsp("decompress " + p("cube.obj.qsp") + " -o " + p("back.obj")).exit_code, 0);
  QuadMesh a = read_mesh_file(p("cube.obj")), b = read_mesh_file(p("back.obj"));
  EXPECT_EQ(a.vertex_count(), b.vertex_count());
  EXPECT_EQ(encode(a), encode(b));
  // compress -> decompress -> compress gives the same bytes.
  ASSERT_EQ(run_qsp("compress " + p("back.obj") + " " + p("again.qsp")).exit_code, 0);
  EXPECT_EQ(read_file_bytes(p("again.qsp")), read_file_bytes(p("cube.obj.qsp")));
  // OFF output by extension, keep-order restores the file's own order.
  ASSERT_EQ(run_qsp("compress --keep-order " + p("cube.obj") + " " + p("k.qsp")).exit_code, 0);
  ASSERT_EQ(run_qsp("decompress " + p("k.qsp") + " " + p("k.off")).exit_code, 0);
  QuadMesh k = read_mesh_file(p("k.off"));
  EXPECT_EQ(k.quads, a.quads);
  EXPECT_EQ(k.positions, a.positions);
}

// --best and the default write files of the same format that decode to the same mesh; stats says
// which level wrote each, and --compat (development versions are gone) is no option.
TEST_F(CliTest, LevelsShareOneFormat) {
  const std::string golden = std::string(QSP_TESTDATA_DIR) + "/golden/tilted_noise_q14.obj";
  ASSERT_EQ(run_qsp("compress --best --quantize 14 " + golden + " " + p("best.qsp")).exit_code, 0);
  ASSERT_EQ(run_qsp("compress --quantize 14 " + golden + " " + p("default.qsp")).exit_code, 0);
  const std::string best = read_file_bytes(p("best.qsp")), dflt = read_file_bytes(p("default.qsp"));
  EXPECT_EQ(inspect(best).level, kMaxLevel);
  EXPECT_EQ(inspect(dflt).level, kDefaultLevel);
  EXPECT_EQ(inspect(best).version_major, kFormatMajor);
  EXPECT_EQ(decode(best).positions, decode(dflt).positions);
  EXPECT_EQ(run_qsp("compress --compat 2.1 " + golden + " " + p("x.qsp")).exit_code, 2);
  // One level: zstd's -19 and a -q14 meant as --quantize 14 are several one-digit levels, refused
  // rather than read as the last of them; nothing is written.
  for (const std::string flags : {"-19", "-q14", "-9 --best", "-1 -4"}) {
    SCOPED_TRACE(flags);
    const CliResult r = run_qsp("compress " + flags + " " + golden + " " + p("many.qsp"));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("levels given"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(p("many.qsp")));
  }
  EXPECT_NE(run_qsp("compress -q14 " + golden + " " + p("many.qsp")).err.find("--quantize 14"),
            std::string::npos);
}

TEST_F(CliTest, RefusesToOverwrite) {
  ASSERT_EQ(run_qsp("compress " + p("cube.obj") + " " + p("x.qsp")).exit_code, 0);
  CliResult r = run_qsp("compress " + p("cube.obj") + " " + p("x.qsp"));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(run_qsp("compress -f " + p("cube.obj") + " " + p("x.qsp")).exit_code, 0);
  // Never the input, not even with -f, not even through a link.
  std::string before = read_file_bytes(p("cube.obj"));
  r = run_qsp("compress -f " + p("cube.obj") + " " + p("cube.obj"));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("input"), std::string::npos) << r.err;
  fs::create_hard_link(p("cube.obj"), p("link.obj"));
  r = run_qsp("compress -f " + p("cube.obj") + " -o " + p("link.obj"));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(read_file_bytes(p("cube.obj")), before);
  // Usage errors exit 2.
  EXPECT_EQ(run_qsp("compress " + p("cube.obj") + " " + p("a.qsp") + " -o " + p("b.qsp")).exit_code, 2);
  EXPECT_EQ(run_qsp("compress --quantize 31 " + p("cube.obj")).exit_code, 2);
}

TEST_F(CliTest, ExtraDataIsRefusedUnlessDropped) {
  {
    std::ofstream o(p("uv.obj"));
    o << "v 0 0 0 1\nv 1 0 0 1\nv 1 1 0 1\nv 0 1 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\ng quad\nvn 0 0 1\n"
         "f 1/1/1 2/2/1 3/3/1 4/4/1\nvp 0.5\n";
  }
  // Texture coordinates, the group, the normal, the vertex weights and the `vp` line (as text) are kept:
  // nothing is refused; nor is a PLY obj_info line (format 3.15), dropped only on request.
  CliResult r = run_qsp("compress -f " + p("uv.obj"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(p("uv.obj.qsp")));
  {
    std::ofstream o(p("info.ply"));
    o << "ply\nformat ascii 1.0\nobj_info scanned 2026\nelement vertex 4\nproperty float x\nproperty float "
         "y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 "
         "0\n"
         "1 1 0\n0 1 0\n4 0 1 2 3\n";
  }
  r = run_qsp("compress " + p("info.ply"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(decode_polygons(read_file_bytes(p("info.ply.qsp"))).ply_info,
            std::vector<std::string>{"scanned 2026"});
  r = run_qsp("compress -f --positions-only " + p("info.ply"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("dropped"), std::string::npos) << r.err;
  r = run_qsp("compress -f --positions-only " + p("uv.obj"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("dropped"), std::string::npos) << r.err;
}

TEST_F(CliTest, StdinAndStdout) {
  ASSERT_EQ(
      std::system(
          (std::string(QSP_CLI_PATH) + " compress - - < " + p("cube.obj") + " > " + p("s.qsp")).c_str()),
      0);
  ASSERT_EQ(
      std::system((std::string(QSP_CLI_PATH) + " decompress - < " + p("s.qsp") + " > " + p("s.obj")).c_str()),
      0);
  EXPECT_EQ(encode(read_mesh_file(p("s.obj"))), encode(read_mesh_file(p("cube.obj"))));
}

TEST_F(CliTest, CorruptFileGivesTypedError) {
  ASSERT_EQ(run_qsp("compress " + p("cube.obj") + " " + p("c.qsp")).exit_code, 0);
  std::string bytes = read_file_bytes(p("c.qsp"));
  bytes[bytes.size() / 2] ^= 0x10;
  write_file_atomic(p("bad.qsp"), bytes, false);
  CliResult r = run_qsp("decompress " + p("bad.qsp") + " " + p("bad.obj"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("checksum"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("bad.obj")));
}

}  // namespace
}  // namespace qsp
