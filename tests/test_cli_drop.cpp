// `--drop LIST` and `--positions-only` end to end (compress, reorder, decompress): a file carrying data .qsp
// does not keep is refused, naming each kind not dropped with its counts and the --drop that drops everything
// the file has; dropping exactly what it has succeeds with one note naming each kind, and the .qsp is the
// bare mesh's, byte for byte. A stray line of prose (MakeHuman files have them) is read, and is the
// `extra` kind, named at its file:line.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/codec.h"
#include "qsp/io.h"
#include "qsp/polymesh.h"
#include "support/cli.h"
#include "support/corpus.h"
#include "support/minor.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::run_qsp;
using testing::slurp;
using testing::spit;

const std::string kSquare = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

// One kind alone: the file's text and what the refusal and the note say of it.
struct Kind {
  const char* name;
  std::string text;
  const char* said;
};

// Each kind, alone on a one-quad mesh (extra: vertex weights; the lines it keeps as text have a test of
// their own below, PLY obj_info lines, the one kind compress does not keep, test_properties.cpp).
std::vector<Kind> kinds() {
  return {
      {"uv", kSquare + "vt 0 0\nvt 1 0\nf 1/1 2/2 3/1 4/2\n",
       "2 texture coordinates, 1 face with texture coordinate indices (uv)"},
      {"normal", kSquare + "vn 0 0 1\nf 1//1 2//1 3//1 4//1\n",
       "1 normal, 1 face with normal indices (normal)"},
      {"color", "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\nf 1 2 3 4\n",
       "4 vertex colours (color)"},
      {"group", kSquare + "o thing\ng a b\nf 1 2 3 4\n", "2 group/object statements (group)"},
      {"material", "mtllib m.mtl\n" + kSquare + "usemtl red\nf 1 2 3 4\n",
       "2 material statements (material)"},
      {"smoothing", kSquare + "s 1\nf 1 2 3 4\n", "1 smoothing group statement (smoothing)"},
      {"tag", kSquare + "f 1 2 3 4\nt corner 1/1/0 0 2.0\nt interpolateboundary 1/0/0 1\n",
       "2 subdivision tags (tag)"},
      {"extra", "v 0 0 0 1\nv 1 0 0 1\nv 1 1 0 1\nv 0 1 0 0.5\nf 1 2 3 4\n",
       "4 vertex weights (v x y z w) (extra)"},
  };
}

// `said` with IN replaced by the input's path.
std::string said(std::string s, const std::string& in) {
  if (const auto at = s.find("IN:"); at != std::string::npos) s.replace(at, 2, in);
  return s;
}

class CliDrop : public testing::TempDirTest {
 protected:
  // The .qsp of `text` compressed with `flags` (exit code 0 asserted by the caller through `err`).
  testing::CliResult compress(const std::string& in, const std::string& flags, const std::string& out) {
    fs::remove(out);
    return run_qsp("compress " + flags + " " + quote(in) + " " + quote(out));
  }
  std::string bare_qsp() {
    spit(p("bare.obj"), kSquare + "f 1 2 3 4\n");
    EXPECT_EQ(compress(p("bare.obj"), "", p("bare.qsp")).exit_code, 0);
    return slurp(p("bare.qsp"));
  }
};

TEST_F(CliDrop, EachKindAloneIsRefusedByNameAndDroppedByName) {
  const std::string bare = bare_qsp();
  for (const Kind& k : kinds()) {
    SCOPED_TRACE(k.name);
    const std::string in = p(std::string(k.name) + ".obj"), out = p("out.qsp");
    spit(in, k.text);
    const std::string what = said(k.said, in);
    // A .qsp keeps texture coordinates (3.2), face labels (3.3), tags (3.4), normals (3.5), colours (3.8),
    // vertex weights (3.14).
    const std::string name = k.name;
    const bool kept = name == "uv" || name == "normal" || name == "color" || name == "group" ||
                      name == "material" || name == "smoothing" || name == "tag" || name == "extra";
    auto r = compress(in, "", out);
    if (kept) {
      ASSERT_EQ(r.exit_code, 0) << r.err;
      EXPECT_EQ(r.err, "");
      const PolygonMesh m = decode_polygons(slurp(out));
      if (name == "uv") {
        EXPECT_EQ(m.texcoords, (std::vector<float>{0, 0, 1, 0}));
      }
      if (name == "color") {  // each vertex keeps its colour, in the canonical order
        ASSERT_EQ(m.vertex_color_components, 3);
        ASSERT_EQ(m.vertex_colors.size(), 12u);
        for (std::size_t v = 0; v < 4; ++v) {
          const float x = m.positions[3 * v], y = m.positions[3 * v + 1];
          const std::vector<float> want = x == 0 && y == 0   ? std::vector<float>{1, 0, 0}
                                          : x == 1 && y == 0 ? std::vector<float>{0, 1, 0}
                                          : x == 1           ? std::vector<float>{0, 0, 1}
                                                             : std::vector<float>{1, 1, 1};
          EXPECT_EQ(std::vector<float>(m.vertex_colors.begin() + 3 * v, m.vertex_colors.begin() + 3 * v + 3),
                    want);
        }
      }
      if (name == "group") {
        EXPECT_EQ(m.objects.names, std::vector<std::string>{"thing"});
        EXPECT_EQ(m.groups.names, std::vector<std::string>{"a b"});
        EXPECT_EQ(m.groups.face, std::vector<std::uint32_t>{0});
      }
      if (name == "material") {
        EXPECT_EQ(m.materials.names, std::vector<std::string>{"red"});
        EXPECT_EQ(m.material_libraries, std::vector<std::string>{"m.mtl"});
      }
      if (name == "smoothing") {
        EXPECT_EQ(m.smoothing.names, std::vector<std::string>{"1"});
      }
      if (name == "normal") {
        EXPECT_EQ(m.normals, (std::vector<float>{0, 0, 1}));
        EXPECT_EQ(m.corner_normals, (std::vector<std::uint32_t>{0, 0, 0, 0}));
      }
      if (name == "extra") {  // each vertex its weight: the vertex property named ""
        ASSERT_EQ(m.vertex_properties.size(), 1u);
        EXPECT_EQ(m.vertex_properties[0].name, "");
        for (std::size_t v = 0; v < 4; ++v) {
          const bool last = m.positions[3 * v] == 0 && m.positions[3 * v + 1] == 1;
          EXPECT_EQ(m.vertex_properties[0].values.at(v), last ? 0.5 : 1.0);
        }
      }
      if (name == "tag") {
        ASSERT_EQ(m.tags.size(), 2u);
        EXPECT_EQ(m.tags[0].name, "corner");
        EXPECT_EQ(m.tags[0].floats, std::vector<double>{2.0});
        EXPECT_EQ(m.tags[1].ints, std::vector<std::int64_t>{1});
      }
    } else {
      EXPECT_EQ(r.exit_code, 1);
      EXPECT_EQ(r.err, "qsp: error: " + in + ": has " + what + ", which .qsp does not keep; pass --drop " +
                           k.name + " (or --positions-only) to drop them\n");
      EXPECT_FALSE(fs::exists(out));
    }
    // Dropping another kind does not help.
    const std::string other = name == "color" ? "uv" : kept ? "color" : "uv";
    r = compress(in, "--drop " + other, out);
    EXPECT_EQ(r.exit_code, kept ? 0 : 1);
    if (!kept) {
      EXPECT_NE(r.err.find("pass --drop " + std::string(k.name) + " (or"), std::string::npos) << r.err;
    }
    // Dropping it: one note, and the bare mesh's bytes.
    r = compress(in, "--drop " + std::string(k.name), out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "qsp: " + in + ": dropped " + what + " (--drop " + k.name + ")\n");
    EXPECT_EQ(slurp(out), bare);
    r = compress(in, "-q --drop " + other + "," + k.name, out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_EQ(slurp(out), bare);
    r = compress(in, "--positions-only", out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "qsp: " + in + ": dropped " + what + " (--positions-only)\n");
    EXPECT_EQ(slurp(out), bare);
    // reorder keeps what compress keeps, written to OUT; the rest is the same refusal and the same way out.
    // Dropped, OUT is the bare mesh.
    const std::string obj = p("out.obj");
    fs::remove(obj);
    r = run_qsp("reorder --like " + quote(p("bare.obj")) + " " + quote(in) + " -o " + quote(obj));
    if (kept) {
      ASSERT_EQ(r.exit_code, 0) << r.err;
      const std::string written = slurp(obj);
      const std::string says = name == "uv"          ? "vt 1 0\n"
                               : name == "normal"    ? "vn 0 0 1\n"
                               : name == "color"     ? "v 1 1 0 0 0 1\n"
                               : name == "group"     ? "g a b\n"
                               : name == "material"  ? "usemtl red\n"
                               : name == "smoothing" ? "s 1\n"
                               : name == "extra"     ? "v 0 1 0 0.5\n"
                                                     : "t corner 1/1/0 0 2\n";
      EXPECT_NE(written.find(says), std::string::npos) << written;
    } else {
      EXPECT_EQ(r.exit_code, 1);
      EXPECT_NE(r.err.find(in + ": has " + what + ", which reorder does not keep; pass --drop " + k.name),
                std::string::npos)
          << r.err;
      EXPECT_FALSE(fs::exists(obj));
    }
    fs::remove(obj);
    r = run_qsp("reorder --drop " + std::string(k.name) + " --like " + quote(p("bare.obj")) + " " +
                quote(in) + " -o " + quote(obj));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("dropped " + what + " (--drop " + k.name + ")"), std::string::npos) << r.err;
    EXPECT_EQ(slurp(obj), kSquare + "f 1 2 3 4\n");
  }
}

// All kinds in one file: every one is named, in --drop's order; leaving any one out of --drop refuses,
// naming that one alone and the whole list; the whole list, `all` and --positions-only succeed.
TEST_F(CliDrop, EveryKindMustBeDroppedAndTheNoteNamesEach) {
  const std::string bare = bare_qsp();
  const std::string in = p("all.obj"), out = p("out.qsp");
  spit(in,
       "# a comment\nmtllib m.mtl\nv 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\nvt 0 0\n"
       "vn 0 0 1\nvp 0.5\no thing\nusemtl red\ns 1\nf 1/1/1 2/1/1 3/1/1 4/1/1\nt corner 1/1/0 0 2.0\n");
  const std::string all = "uv,normal,color,group,material,smoothing,tag,extra";
  const std::string described =
      "1 texture coordinate, 1 face with texture coordinate indices (uv), 1 normal, 1 face with normal "
      "indices (normal), 4 vertex colours (color), 1 group/object statement (group), 2 material statements "
      "(material), 1 smoothing group statement (smoothing), 1 subdivision tag (tag), 1 line qsp keeps only "
      "as text, the first at " +
      in + ":9: `vp` (parameter-space vertex) (extra)";
  // With the leading comment dropped too: named in --drop's order, before extra.
  std::string with_comment = described;
  with_comment.insert(with_comment.find("1 line qsp keeps"), "1 leading comment line (comment), ");
  // Nothing is refused: every kind is kept (the vp line as text, with a warning).
  auto r = compress(in, "", out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + in + ": keeping 1 line"), std::string::npos) << r.err;
  {
    const PolygonMesh m = decode_polygons(slurp(out));
    EXPECT_EQ(m.vertex_color_components, 3);
    EXPECT_EQ(m.texcoord_components, 2);
    EXPECT_EQ(m.tags.size(), 1u);
    EXPECT_EQ(m.kept_lines, std::vector<std::string>{"vp 0.5"});
  }
  r = compress(in, "--drop " + all, out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "qsp: " + in + ": dropped " + described + " (--drop " + all + ")\n");
  // The leading comment is kept: the bare mesh's sections and a comments section.
  EXPECT_EQ(file_comments(slurp(out)), std::vector<std::string>{" a comment"});
  EXPECT_EQ(slurp(out), with_comments(bare, {" a comment"}));
  for (const std::string& flags : std::vector<std::string>{
           "--drop all", "--positions-only", "--positions-only --drop uv", "--drop " + all + ",comment"}) {
    SCOPED_TRACE(flags);
    r = compress(in, flags, out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("dropped " + with_comment), std::string::npos) << r.err;
    EXPECT_EQ(slurp(out), bare);
  }
}

TEST_F(CliDrop, AnUnknownItemIsAUsageErrorNamingTheValidOnes) {
  spit(p("in.obj"), kSquare + "vt 0 0\nf 1 2 3 4\n");
  for (const std::string& list : std::vector<std::string>{"uv,texture", "uv,", "UV", ",", "normals"}) {
    SCOPED_TRACE(list);
    for (const std::string& cmd : std::vector<std::string>{
             "compress -c ", "reorder -o " + quote(p("o.obj")) + " --like " + quote(p("in.obj")) + " "}) {
      const auto r = run_qsp(cmd + "--drop " + quote(list) + " " + quote(p("in.obj")));
      EXPECT_EQ(r.exit_code, 2) << r.err;
      EXPECT_NE(
          r.err.find("(expected uv, normal, color, group, material, smoothing, tag, comment, extra or all)"),
          std::string::npos)
          << r.err;
      EXPECT_EQ(r.out, "");
    }
  }
  // colour is color.
  EXPECT_EQ(run_qsp("compress -f --drop colour,uv " + quote(p("in.obj"))).exit_code, 0);
}

// The leading comment block (licence lines) is kept in the .qsp's comments section and written back by
// decompress; --drop comment drops it and says so. Comments after it are not kept (README says so).
TEST_F(CliDrop, TheLeadingCommentBlockIsKeptUnlessDropped) {
  const std::string bare = bare_qsp();
  spit(p("c.obj"), "# licence\n\n  #more \n" + kSquare + "# later\nf 1 2 3 4 # end of line\n");
  auto r = compress(p("c.obj"), "", p("c.qsp"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(slurp(p("c.qsp")), with_comments(bare, {" licence", "more "}));
  r = run_qsp("decompress -c " + quote(p("c.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "# licence\n#more \n" + kSquare + "f 1 2 3 4\n");
  r = run_qsp("stats " + quote(p("c.qsp")));
  EXPECT_NE(r.out.find("format 3.1"), std::string::npos) << r.out;
  r = compress(p("c.obj"), "--drop comment", p("c.qsp"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "qsp: " + p("c.obj") + ": dropped 2 leading comment lines (comment) (--drop comment)\n");
  EXPECT_EQ(slurp(p("c.qsp")), bare);
  // reorder keeps them too, into OBJ and into .qsp.
  spit(p("bare.obj"), kSquare + "f 1 2 3 4\n");
  r = run_qsp("reorder --like " + quote(p("bare.obj")) + " " + quote(p("c.obj")) + " -o " +
              quote(p("r.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(slurp(p("r.obj")), "# licence\n#more \n" + kSquare + "f 1 2 3 4\n");
  ASSERT_EQ(compress(p("c.obj"), "", p("c.qsp")).exit_code, 0);
  r = run_qsp("reorder --like " + quote(p("bare.obj")) + " " + quote(p("c.qsp")) + " -o " +
              quote(p("r.obj")) + " -f");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(slurp(p("r.obj")), "# licence\n#more \n" + kSquare + "f 1 2 3 4\n");
}

// Issue 19's MakeHuman case: a stray line of prose between the licence comments and the vertices. Read
// (stats and the like accept it), kept by compress with a warning naming it at its line and written back
// by decompress before the vertices (format 3.7's kept lines section); --drop extra drops it, and then the
// .qsp is the untouched file's, byte for byte. reorder refuses it until dropped, and its OBJ is then the
// untouched file's.
TEST_F(CliDrop, AStrayLineOfProseInAMakeHumanHeaderIsKept) {
  const std::string fedora = slurp(fs::path(QSP_TESTDATA_DIR) / "mh_fedora.obj");
  const std::size_t first_v = fedora.find("\nv ") + 1;
  ASSERT_NE(fedora.substr(0, first_v).find("# "), std::string::npos);  // after the header comments
  const std::string hat = p("hat.obj"), plain = p("plain.obj");
  spit(plain, fedora);
  spit(hat, fedora.substr(0, first_v) + "This asset was converted by hand\n" + fedora.substr(first_v));
  const long line = std::count(fedora.begin(), fedora.begin() + static_cast<long>(first_v), '\n') + 1;
  const std::string where = hat + ":" + std::to_string(line) + ": unknown statement 'This'";

  auto r = run_qsp("stats --json " + quote(hat));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::string as_plain = r.out;
  for (auto at = as_plain.find(hat); at != std::string::npos; at = as_plain.find(hat, at))
    as_plain.replace(at, hat.size(), plain);
  EXPECT_EQ(as_plain, run_qsp("stats --json " + quote(plain)).out);
  r = compress(hat, "", p("hat.qsp"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "qsp: warning: " + hat + ": keeping 1 line qsp keeps only as text, the first at " + where +
                       " (extra); decompress writes them back before the vertices\n");
  EXPECT_EQ(decode_polygons(slurp(p("hat.qsp"))).kept_lines,
            std::vector<std::string>{"This asset was converted by hand"});
  EXPECT_EQ(static_cast<int>(slurp(p("hat.qsp"))[9]), testing::minor_of_file_with(slurp(p("hat.qsp")), 7))
      << "a file with kept lines says format 3.7 (3.16 with the licence block coded or hints in its texture "
         "coordinates)";
  r = run_qsp("decompress -c " + quote(p("hat.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::size_t prose = r.out.find("\nThis asset was converted by hand\n");
  EXPECT_NE(prose, std::string::npos);
  EXPECT_LT(prose, r.out.find("\nv ")) << "before the vertices";
  EXPECT_GT(prose, r.out.find("\n#")) << "after the licence comments";
  EXPECT_EQ(compress(hat, "-q", p("hat.qsp")).err, "");
  r = compress(hat, "--drop uv,extra", p("hat.qsp"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(
      r.err.find("dropped 702 texture coordinates, 622 faces with texture coordinate indices (uv), 1 line "
                 "qsp keeps only as text, the first at " +
                 where + " (extra) (--drop uv,extra)"),
      std::string::npos)
      << r.err;
  // The comments before the prose line are the leading block, kept.
  EXPECT_EQ(file_comments(slurp(p("hat.qsp"))), leading_comments(slurp(plain)));
  EXPECT_FALSE(file_comments(slurp(p("hat.qsp"))).empty());
  ASSERT_EQ(compress(hat, "--drop uv,extra,comment", p("hat.qsp")).exit_code, 0);
  ASSERT_EQ(compress(plain, "--drop uv,comment", p("plain.qsp")).exit_code, 0);
  EXPECT_EQ(slurp(p("hat.qsp")), slurp(p("plain.qsp")));
  ASSERT_EQ(compress(hat, "--positions-only", p("hat.qsp")).exit_code, 0);
  EXPECT_EQ(slurp(p("hat.qsp")), slurp(p("plain.qsp")));

  // reorder keeps the line too, before the vertices, unless extra is dropped; OFF cannot hold it: refused,
  // with no note that it is being kept.
  r = run_qsp("reorder --drop uv --like " + quote(plain) + " " + quote(hat) + " -o " + quote(p("out.off")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("lines kept as text"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("keeping"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("out.off")));

  r = run_qsp("reorder --drop uv --like " + quote(plain) + " " + quote(hat) + " -o " + quote(p("out.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("keeping 1 line"), std::string::npos) << r.err;
  EXPECT_LT(slurp(p("out.obj")).find("\nThis asset was converted by hand\n"),
            slurp(p("out.obj")).find("\nv "));
  r = run_qsp("reorder --drop uv,extra --like " + quote(plain) + " " + quote(hat) + " -f -o " +
              quote(p("out.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(
      run_qsp("reorder --drop uv --like " + quote(plain) + " " + quote(plain) + " -o " + quote(p("want.obj")))
          .exit_code,
      0);
  EXPECT_EQ(slurp(p("out.obj")), slurp(p("want.obj")));
}

// An OBJ whose faces name texture coordinates or normals is read by the exact reader alone; behind 70
// comment lines after its last face (which compress does not keep) the same text goes the other way,
// quad reader first. Both must give the same file and say the same, whatever is dropped, on every
// corpus mesh that has UVs or normals.
TEST_F(CliDrop, OneReaderAndTwoReadersGiveTheSameFileAndWords) {
  QSP_NEEDS_SHARED();
  int tried = 0;
  for (const fs::path& mesh : testing::shared_meshes()) {
    if (mesh.extension() != ".obj") continue;
    const std::string text = slurp(mesh.string());
    if (text.find("\nvt ") == std::string::npos && text.find("\nvn ") == std::string::npos) continue;
    SCOPED_TRACE(mesh.string());
    ++tried;
    std::string padded = text;
    for (int i = 0; i < 70; ++i) padded += "# after the faces\n";
    const std::string one = p("m.obj"), two = p("padded/m.obj");  // one name: the same words
    fs::create_directories(p("padded"));
    spit(one, text);
    spit(two, padded);
    for (const char* flags :
         {"", "--drop uv", "--drop normal", "-q --quantize 14 --quantize-uv 12 --quantize-normal 10",
          "--drop group,material,smoothing"}) {
      SCOPED_TRACE(flags);
      const testing::CliResult a = compress(one, flags, p("one.qsp")), b = compress(two, flags, p("two.qsp"));
      ASSERT_EQ(a.exit_code, b.exit_code) << a.err << b.err;
      std::string words = b.err;
      for (std::size_t at; (at = words.find(two)) != std::string::npos;) words.replace(at, two.size(), one);
      EXPECT_EQ(a.err, words);
      if (a.exit_code == 0) {
        EXPECT_EQ(slurp(p("one.qsp")), slurp(p("two.qsp")));
      }
    }
  }
  EXPECT_GE(tried, 10);
}

// decompress: an output format that cannot hold what the .qsp carries refuses it, naming each kind with
// the --drop that drops it, and writes nothing; with those dropped it writes the mesh, saying what it
// dropped. The positions and faces are the full decode's (read here as text, not through qsp's reader).
TEST_F(CliDrop, DecompressDropsWhatTheOutputFormatCannotHold) {
  spit(p("all.obj"),
       "# licence line\nmtllib a.mtl\nsome prose\no thing\n" + kSquare +
           "v 2 0 0\nv 2 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\ng left\nusemtl red\ns 1\n"
           "f 1/1/1 2/2/1 3/3/1 4/4/1\ng right\nusemtl blue\ns off\nf 2/1/1 5/2/1 6/3/1 3/4/1\n"
           "t crease 2/1/0 1 2 5.0\n");
  ASSERT_EQ(run_qsp("compress -q " + quote(p("all.obj")) + " " + quote(p("all.qsp"))).exit_code, 0);
  ASSERT_EQ(run_qsp("decompress -q " + quote(p("all.qsp")) + " -o " + quote(p("full.obj"))).exit_code, 0);
  // Each line of a kind: "v x y z" and the faces' vertex indices alone.
  const auto lines = [](const std::string& text, const std::string& kind) {
    std::vector<std::string> out;
    std::size_t at = 0;
    while (at < text.size()) {
      const std::size_t end = std::min(text.find('\n', at), text.size());
      std::string line = text.substr(at, end - at);
      at = end + 1;
      if (line.rfind(kind + " ", 0) != 0) continue;
      if (kind == "f") {
        std::string bare = "f";
        for (std::size_t i = 2; i < line.size();) {
          const std::size_t next = std::min(line.find(' ', i), line.size());
          const std::string word = line.substr(i, next - i);
          bare.append(" ").append(word, 0, word.find('/'));
          i = next + 1;
        }
        line = bare;
      }
      out.push_back(line);
    }
    return out;
  };
  const std::string full = slurp(p("full.obj"));
  ASSERT_EQ(lines(full, "v").size(), 6u);
  ASSERT_EQ(lines(full, "f").size(), 2u);

  testing::CliResult r = run_qsp("decompress " + quote(p("all.qsp")) + " -o " + quote(p("out.off")));
  EXPECT_EQ(r.exit_code, 1);
  for (const char* said : {"OFF cannot hold", "(--drop uv)", "(--drop normal)", "(--drop group)",
                           "(--drop material)", "(--drop smoothing)", "(--drop tag)", "(--drop extra)"})
    EXPECT_NE(r.err.find(said), std::string::npos) << said << "\n" << r.err;
  EXPECT_FALSE(fs::exists(p("out.off")));
  // Dropping all but one kind is still refused, naming that one.
  r = run_qsp("decompress --drop uv,normal,group,material,smoothing,extra " + quote(p("all.qsp")) + " -o " +
              quote(p("out.off")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("(--drop tag)"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("(--drop uv)"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("out.off")));

  r = run_qsp("decompress --drop uv,normal,group,material,smoothing,tag,extra " + quote(p("all.qsp")) +
              " -o " + quote(p("out.off")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("dropped its uv, normal, group, material, smoothing, tag, extra (--drop "),
            std::string::npos)
      << r.err;
  const std::string off = slurp(p("out.off"));
  EXPECT_NE(off.find("# licence line\n"), std::string::npos) << "the comment block is kept unless dropped";
  // OFF: the counts line after the header and comments, then "x y z" and "4 a b c d" (0-based).
  std::vector<std::string> rows;
  for (std::size_t at = 0; at < off.size();) {
    const std::size_t end = std::min(off.find('\n', at), off.size());
    const std::string line = off.substr(at, end - at);
    at = end + 1;
    if (!line.empty() && line[0] != '#' && line != "OFF") rows.push_back(line);
  }
  ASSERT_EQ(rows.size(), 1u + 6u + 2u) << off;
  EXPECT_EQ(rows[0], "6 2 0");
  const std::vector<std::string> v = lines(full, "v"), f = lines(full, "f");
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(rows[1 + i], v[i].substr(2));
  for (std::size_t i = 0; i < 2; ++i) {
    std::string one_based = "f";
    std::size_t pos = 2;  // past "4 "
    const std::string& row = rows[7 + i];
    while (pos < row.size()) {
      const std::size_t next = std::min(row.find(' ', pos), row.size());
      one_based.append(" ").append(std::to_string(std::stoul(row.substr(pos, next - pos)) + 1));
      pos = next + 1;
    }
    EXPECT_EQ(one_based, f[i]);
  }

  // --positions-only to OBJ: the bare mesh, the comment block dropped too, and said.
  r = run_qsp("decompress --positions-only " + quote(p("all.qsp")) + " -o " + quote(p("bare.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("dropped its uv, normal, group, material, smoothing, tag, comment, extra "
                       "(--positions-only)"),
            std::string::npos)
      << r.err;
  const std::string bare = slurp(p("bare.obj"));
  EXPECT_EQ(lines(bare, "v"), v);
  EXPECT_EQ(lines(bare, "f"), f);
  for (const char* kind : {"vt ", "vn ", "g ", "o ", "usemtl ", "mtllib ", "s ", "t ", "#", "some"})
    EXPECT_EQ(bare.find(kind), std::string::npos) << kind;
  // -q says nothing; an unknown kind is a usage error.
  r = run_qsp("decompress -q -f --positions-only " + quote(p("all.qsp")) + " -o " + quote(p("bare.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  r = run_qsp("decompress --drop bogus " + quote(p("all.qsp")) + " -o " + quote(p("x.obj")));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown category 'bogus'"), std::string::npos) << r.err;
}

// The same where the .qsp keeps the OBJ's statement order (Blender's interleaved objects) and float64
// colours: what is dropped leaves no statement or exact copy behind, and the rest is written in order.
TEST_F(CliDrop, DecompressDropsFromAKeptOrderAndExactValues) {
  spit(p("o.obj"),
       "o a\nv 0 0 0 0.123456789012 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\n"
       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n"
       "o b\nv 2 0 0 1 0 0\nv 2 1 0 0 1 0\nvt 0.5 0.5\nf 2/1 5/2 6/5 3/3\n");
  testing::CliResult r = run_qsp("compress -q --keep-order " + quote(p("o.obj")) + " " + quote(p("o.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* drop : {"uv", "group", "color", "uv,group", "uv,color,group"}) {
    SCOPED_TRACE(drop);
    r = run_qsp(std::string("decompress -f --drop ") + drop + " " + quote(p("o.qsp")) + " -o " +
                quote(p("d.obj")));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find(std::string("(--drop ") + drop + ")"), std::string::npos) << r.err;
    const std::string text = slurp(p("d.obj"));
    const std::string d = drop;
    EXPECT_EQ(text.find("vt ") == std::string::npos, d.find("uv") != std::string::npos) << text;
    EXPECT_EQ(text.find("o ") == std::string::npos, d.find("group") != std::string::npos) << text;
    EXPECT_EQ(text.find("0.123456789012") == std::string::npos, d.find("color") != std::string::npos) << text;
    // The kept order: the second object's vertices after the first's face.
    EXPECT_LT(text.find("f "), text.find("v 2 0 0")) << text;
  }
  r = run_qsp("decompress -f --positions-only " + quote(p("o.qsp")) + " -o " + quote(p("d.off")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(slurp(p("d.off")).substr(0, 4), "OFF\n");
}

}  // namespace
}  // namespace qsp
