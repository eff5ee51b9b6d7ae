// The statement order (format 3.11, the optional statement order section): with --keep-order an OBJ
// comes back with its statements in its order (v, vt, vn and f runs interleaved as they were, o, g,
// usemtl and s where they stood, names no face takes, tags, kept lines), checked on every corpus OBJ by
// reading both files' lines, not through qsp's reader; the section is written only where that order is
// not the one a decoder writes anyway; every prefix, bit flip and cut of it is refused or decodes to
// statements a writer can follow.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "codec_sections.h"
#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/polymesh.h"
#include "support/cli.h"
#include "support/corpus.h"
#include "support/files.h"
#include "support/minor.h"
#include "support/section_sweep.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;

const std::string kInterleaved =
    std::string(QSP_TESTDATA_DIR) + "/golden/statements/interleaved_keep_order.obj";

// An OBJ's statements as its lines say them: runs of v, vt, vn, f, t and mtllib lines as (keyword,
// count) (their numbers may be spelt otherwise), every other line but comments and blank ones by its
// words (o, g, usemtl, s with their names; lines kept as text).
std::vector<std::string> statement_lines(const std::string& text) {
  std::vector<std::string> out;
  std::string run;
  std::size_t count = 0;
  const auto end_run = [&] {
    if (count) out.push_back(run + " x" + std::to_string(count));
    count = 0;
  };
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string word, joined;
    std::vector<std::string> all;
    while (words >> word) all.push_back(word);
    if (all.empty() || all[0][0] == '#') continue;
    const std::string& k = all[0];
    if (k == "v" || k == "vt" || k == "vn" || k == "f" || k == "t" || k == "mtllib") {
      if (k != run) end_run(), run = k;
      ++count;
      continue;
    }
    end_run();
    run.clear();
    for (const std::string& w : all) joined += (joined.empty() ? "" : " ") + w;
    out.push_back(joined);
  }
  end_run();
  return out;
}

TEST(Statements, EveryCorpusObjComesBackInItsOrder) {
  testing::TempDir dir;
  int kept = 0, files = 0;
  std::vector<fs::path> paths = testing::shared_meshes();
  paths.push_back(kInterleaved);
  for (const fs::path& f : paths) {
    if (f.extension() != ".obj") continue;
    const std::string text = testing::slurp(f);
    if (text.find("\\\n") != std::string::npos || text.find("\\\r") != std::string::npos) continue;
    SCOPED_TRACE(f.string());
    const std::string q = dir.p("m.qsp"), back = dir.p("back.obj");
    const auto r = testing::run_qsp("compress -f -q --keep-order " + testing::quote(f.string()) + " " +
                                    testing::quote(q));
    if (r.exit_code != 0) {
      // Only what is not a mesh (a face repeating a vertex) is refused.
      EXPECT_NE(r.err.find("repeats vertex"), std::string::npos) << r.err;
      continue;
    }
    ++files;
    const auto d = testing::run_qsp("decompress -f -q " + testing::quote(q) + " -o " + testing::quote(back));
    ASSERT_EQ(d.exit_code, 0) << d.err;
    EXPECT_EQ(statement_lines(testing::slurp(back)), statement_lines(text));
    const FileInfo info = inspect(testing::slurp(q));
    for (const SectionInfo& s : info.sections) kept += s.tag == container::kTagStatements;
  }
  // Without the shared meshes (a clone alone), the testdata file only.
  EXPECT_GE(files, testing::shared_present() ? 20 : 1);
  EXPECT_GE(kept, testing::shared_present() ? 5 : 1) << "OBJs whose order is not the canonical writer's";
}

TEST(Statements, OnlyWithKeepOrderAndOnlyWhereTheOrderIsNotTheWritersOwn) {
  const PolygonMesh m = to_polygon_mesh(read_obj_mesh(testing::slurp(kInterleaved), kInterleaved),
                                        kPolygonMeshCategories | kCategoryExtra);
  ASSERT_FALSE(m.statements.empty());
  EXPECT_TRUE(statements_needed(m));
  EncodeOptions o;
  const auto has = [](const std::string& bytes) {
    return container::parse(bytes).find(container::kTagStatements) != nullptr;
  };
  EXPECT_FALSE(has(encode_polygons(m, o))) << "without --keep-order the faces are renumbered anyway";
  o.keep_order = true;
  const std::string bytes = encode_polygons(m, o);
  EXPECT_TRUE(has(bytes));
  EXPECT_EQ(static_cast<int>(bytes[9]), testing::minor_of_file_with(bytes, kFormatMinorStatements));
  // The order the writer gives the decoded mesh without the section is not stored.
  PolygonMesh plain = decode_polygons(bytes);
  plain.statements.clear();
  const std::string canonical = write_obj_mesh(from_polygon_mesh(plain));
  PolygonMesh again = to_polygon_mesh(read_obj_mesh(canonical, "canonical.obj"), kPolygonMeshCategories);
  EXPECT_FALSE(statements_needed(again));
  EXPECT_FALSE(has(encode_polygons(again, o)));
}

TEST(Statements, HostileSectionsAreRefusedWithTheirOffset) {
  const PolygonMesh m = to_polygon_mesh(read_obj_mesh(testing::slurp(kInterleaved), kInterleaved),
                                        kPolygonMeshCategories | kCategoryExtra);
  EncodeOptions o;
  o.keep_order = true;
  const std::string good = encode_polygons(m, o);
  const PolygonMesh back = decode_polygons(good);
  // Hand-made payloads: (kind, value) pairs after their count.
  const auto refused = [&](const std::string& payload, const char* what) {
    SCOPED_TRACE(what);
    try {
      (void)decode_statements_section(payload, 100, back);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kFormat) << e.what();
      EXPECT_NE(std::string(e.what()).find("byte offset"), std::string::npos) << e.what();
    }
  };
  refused(std::string("\x00", 1), "no statement");
  refused(std::string("\x01\x0a\x01", 3), "a comment run");
  refused(std::string("\x01\x0c\x01", 3), "an unknown kind");
  refused(std::string("\x01\x00\x07", 3), "a run of 7 vertices where there are 6");
  refused(std::string("\x02\x00\x06\x03\x02", 5), "faces and vertices short of their counts");
  refused(std::string("\x01\x05\x09", 3), "a group beyond the names");
  refused(std::string("\x01\x00\x00", 3), "an empty run");
  // Faces whose labels no statement set.
  refused(std::string("\x05\x00\x06\x01\x05\x08\x01\x00\x03\x02", 10), "faces without their labels");
  const int decoded = testing::sweep_section(good, container::kTagStatements, kFormatMinorStatements,
                                             [](const PolygonMesh& got) {
                                               Mesh w = from_polygon_mesh(got);
                                               EXPECT_NO_THROW(check_mesh(w));
                                               EXPECT_NO_THROW((void)write_obj_mesh(w));
                                             });
  EXPECT_GE(decoded, 0);
}

}  // namespace
}  // namespace qsp
