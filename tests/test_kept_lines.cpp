// Kept lines (format 3.7, the optional kept lines section): OBJ lines qsp keeps only as text come back
// in order; a line that would read as a statement when written back is refused by encoder and decoder;
// the quad reader skips the section; every prefix, bit flip and cut of it is refused or decodes to lines
// that read back as kept text.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "codec_sections.h"
#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "support/files.h"
#include "support/polygon.h"
#include "support/section_sweep.h"

namespace qsp {
namespace {

const std::string kGrid = std::string(QSP_TESTDATA_DIR) + "/golden/kept/grid_prose.obj";

TEST(KeptLines, FilesKeepThemInOrderAndRenumberedCopiesGiveTheSameBytes) {
  const PolygonMesh m = testing::read_obj_polygons(kGrid);
  ASSERT_EQ(m.kept_lines, (std::vector<std::string>{
                              "This 2x2 grid was exported by hand, a line of prose before its vertices",
                              "cstype bspline", "vp 0.5 0.5", "deg 3\t3"}));
  for (int level : {1, 9}) {
    EncodeOptions o;
    o.level = level;
    const std::string bytes = encode_polygons(m, o);
    EXPECT_EQ(static_cast<int>(bytes[9]), 7);
    PolygonMesh copy = testing::renumbered(m, 3);
    copy.kept_lines = m.kept_lines;
    EXPECT_EQ(encode_polygons(copy, o), bytes);
    EXPECT_EQ(decode_polygons(bytes).kept_lines, m.kept_lines);
    o.keep_order = true;
    EXPECT_EQ(decode_polygons(encode_polygons(m, o)).kept_lines, m.kept_lines);
    // The quad reader skips the optional section: the same quads.
    EXPECT_EQ(decode(bytes).quads, decode_polygons(bytes).corners);
    // A comments section goes before it, in tag order.
    const std::string with = with_comments(bytes, {" licence"});
    EXPECT_EQ(file_comments(with), std::vector<std::string>{" licence"});
    EXPECT_EQ(decode_polygons(with).kept_lines, m.kept_lines);
  }
}

TEST(KeptLines, ALineThatWouldReadAsAStatementIsRefusedBothWays) {
  PolygonMesh m = testing::read_obj_polygons(kGrid);
  const std::string good = encode_polygons(m);
  for (const std::string& line : std::vector<std::string>{
           "v 1 2 3", "f 1 2 3", "t crease 2/1 1 2 4", "g x", "usemtl red", "# note", " lead", "trail ",
           "joined \\", "", std::string("a\x01z"), "mtllib a.mtl", "curv 0 1 2"}) {
    SCOPED_TRACE(line);
    EXPECT_FALSE(kept_line_problem(line).empty());
    m.kept_lines = {"fine line", line};
    EXPECT_THROW(encode_polygons(m), Error);
    std::string payload;
    payload += '\x02';
    payload += '\x09';
    payload += "fine line";
    payload += static_cast<char>(line.size());
    payload += line;
    try {
      decode_polygons(container::with_section(good, container::kTagKeptLines, payload, 7));
      FAIL() << "decoded";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kFormat);
      EXPECT_NE(std::string(e.what()).find("kept line 1"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("byte offset"), std::string::npos) << e.what();
    }
  }
  for (const std::string& line :
       std::vector<std::string>{"vp 0.5", "cstype bspline", "This is prose", "tx 1", "a\tb", "vt2 1"})
    EXPECT_EQ(kept_line_problem(line), "") << line;
}

TEST(KeptLines, EveryPrefixBitFlipAndCutIsSafe) {
  const std::string good = testing::slurp(std::string(QSP_TESTDATA_DIR) + "/golden/kept/grid_prose.qsp");
  testing::sweep_section(good, container::kTagKeptLines, 7, [](const PolygonMesh& got) {
    for (const std::string& line : got.kept_lines) ASSERT_EQ(kept_line_problem(line), "") << line;
  });
}

}  // namespace
}  // namespace qsp
