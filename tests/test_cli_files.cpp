// The CLI's file handling end to end (tools/qsp/shared.h): gzip's rules for inputs and outputs, no
// output ever an input or another output, links, batches that go on after a bad file, standard input
// in any format, and messages that name the way out. Each case checks the exit code, the files left
// afterwards (inputs byte-identical) and the message.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "qsp/codec.h"
#include "qsp/io.h"
#include "support/cli.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::run_qsp;

using testing::slurp;
using testing::spit;

const std::string kData = QSP_TESTDATA_DIR;

// A fresh folder per test; `snapshot` records files whose bytes must not change.
class CliFiles : public testing::TempDirTest {
 protected:
  // Copies a bundled mesh into the folder as `name` and remembers its bytes.
  std::string add(const std::string& bundled, const std::string& name) {
    fs::create_directories(fs::path(p(name)).parent_path());
    fs::copy_file(kData + "/" + bundled, p(name), fs::copy_options::overwrite_existing);
    inputs_[name] = slurp(p(name));
    return p(name);
  }
  std::string add_bytes(const std::string& name, const std::string& bytes) {
    fs::create_directories(fs::path(p(name)).parent_path());
    spit(p(name), bytes);
    inputs_[name] = bytes;
    return p(name);
  }
  // Every file below the folder, relative, sorted (links as themselves, empty folders as "name/").
  std::vector<std::string> listing() const {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir_)) {
      const std::string name = e.path().lexically_relative(dir_).string();
      if (e.is_symlink() || !e.is_directory())
        out.push_back(name);
      else if (fs::is_empty(e.path()))
        out.push_back(name + "/");
    }
    std::sort(out.begin(), out.end());
    return out;
  }
  void expect_inputs_unchanged() const {
    for (const auto& [name, bytes] : inputs_) EXPECT_TRUE(slurp(p(name)) == bytes) << name << " was changed";
  }
  // `in` compressed by the library with the CLI's defaults: what `compress` must have written (its
  // leading comment block kept).
  static std::string encoded(const std::string& in) {
    ReadReport report;
    const std::string bytes = encode(read_mesh_file(in, &report));
    return report.leading_comments.empty() ? bytes : with_comments(bytes, report.leading_comments);
  }
  // What `decompress` must write for `bytes`: the mesh after its comments.
  static std::string decoded(const std::string& bytes) {
    return write_obj(decode(bytes), file_comments(bytes));
  }

  std::map<std::string, std::string> inputs_;
};

TEST_F(CliFiles, SeveralInputsAreEachWrittenBesideThemselves) {
  // The report's case: `compress -f *.obj` must not take the second mesh as the output.
  const std::string a = add("cube_4.obj", "a.obj"), b = add("l_shape.obj", "b.obj");
  auto r = run_qsp("compress -f " + quote(a) + " " + quote(b));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.obj", "a.obj.qsp", "b.obj", "b.obj.qsp"}));
  expect_inputs_unchanged();
  EXPECT_TRUE(slurp(p("a.obj.qsp")) == encoded(a));
  EXPECT_TRUE(slurp(p("b.obj.qsp")) == encoded(b));
  // ... and back, each beside itself, refusing the names that exist (the source meshes).
  r = run_qsp("decompress " + quote(p("a.obj.qsp")) + " " + quote(p("b.obj.qsp")));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find(a + ": already exists"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(b + ": already exists"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("pass -f"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--output-dir"), std::string::npos) << r.err;
  expect_inputs_unchanged();
}

TEST_F(CliFiles, AnOutputNameMustSayWhatItHolds) {
  const std::string a = add("cube_4.obj", "a.obj"), b = add("l_shape.obj", "b.obj");
  // IN OUT with a mesh name for the .qsp: refused before anything is written, naming the rule.
  auto r = run_qsp("compress " + quote(a) + " " + quote(p("out.obj")));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(
      r.err.find("out.obj: no such file to compress; if it is meant as the output, its name must end in "
                 ".qsp"),
      std::string::npos)
      << r.err;
  r = run_qsp("compress " + quote(a) + " -o " + quote(p("out.obj")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("must not take a mesh name; name it"), std::string::npos) << r.err;
  // An OUT after several inputs, -o or -c with several: usage errors naming --output-dir.
  for (const std::string& args :
       {quote(a) + " " + quote(b) + " " + quote(p("c.qsp")),
        quote(a) + " " + quote(b) + " -o " + quote(p("c.qsp")), quote(a) + " " + quote(b) + " -c"}) {
    SCOPED_TRACE(args);
    r = run_qsp("compress " + args);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--output-dir"), std::string::npos) << r.err;
  }
  // decompress: OUT must be a mesh name, a .qsp without .qsp gets no made-up name.
  r = run_qsp("compress " + quote(a));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_qsp("decompress " + quote(p("a.obj.qsp")) + " " + quote(p("back.txt")));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("must end in .obj, .off or .ply"), std::string::npos) << r.err;
  fs::copy_file(p("a.obj.qsp"), p("a.bin"));
  r = run_qsp("decompress " + quote(p("a.bin")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("does not end in .qsp"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("-o NAME"), std::string::npos) << r.err;
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.bin", "a.obj", "a.obj.qsp", "b.obj"}));
  expect_inputs_unchanged();
}

TEST_F(CliFiles, OutputDirAndStandardOutput) {
  const std::string a = add("cube_4.obj", "a.obj"), b = add("l_shape.obj", "sub/b.obj");
  auto r = run_qsp("compress --output-dir " + quote(p("packed")) + " " + quote(a) + " " + quote(b));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(slurp(p("packed/a.obj.qsp")) == encoded(a));
  EXPECT_TRUE(slurp(p("packed/b.obj.qsp")) == encoded(b));
  r = run_qsp("decompress --output-dir " + quote(p("back")) + " " + quote(p("packed/a.obj.qsp")) + " " +
              quote(p("packed/b.obj.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.obj", "back/a.obj", "back/b.obj", "packed/a.obj.qsp",
                                                 "packed/b.obj.qsp", "sub/b.obj"}));
  EXPECT_TRUE(encoded(p("back/b.obj")) == encoded(b));
  // -c: one input to standard output; the file holds exactly what -o would have written.
  r = run_qsp("compress -c " + quote(a));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out == encoded(a));
  r = run_qsp("decompress -c " + quote(p("packed/a.obj.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out == decoded(encoded(a)));
  // Two inputs of one name into one folder would be written twice: refused, nothing written.
  r = run_qsp("compress --output-dir " + quote(p("flat")) + " " + quote(b) + " " +
              quote(add("cube_4.obj", "b.obj")));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("would be written twice"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("flat/b.obj.qsp")));
  expect_inputs_unchanged();
}

// One check for every subcommand: no output is an input or another output, by name, path or link.
TEST_F(CliFiles, NoOutputIsAnInputOrAnotherOutput) {
  const std::string a = add("cube_4.obj", "a.obj");
  const std::string b = add("cube_4.obj", "b.obj");
  fs::create_directory(p("sub"));
  fs::create_symlink(a, p("link_to_a.obj"));
  fs::create_hard_link(a, p("hard_a.txt"));
  const std::vector<std::string> cases = {
      "match -f " + quote(a) + " " + quote(b) + " -o " + quote(a),  // the report's case
      "match -f " + quote(a) + " " + quote(b) + " -o " + quote(p("sub/../b.obj")),
      "match -f " + quote(a) + " " + quote(b) + " -o " + quote(p("link_to_a.obj")),
      "match -f " + quote(a) + " " + quote(b) + " --faces " + quote(p("hard_a.txt")),
      "reorder -f --like " + quote(a) + " " + quote(b) + " -o " + quote(p("link_to_a.obj")),
      "compress -f " + quote(a) + " -o " + quote(p("hard_a.txt")),
      "compress -f " + quote(p("link_to_a.obj")) + " -o " + quote(a),
  };
  for (const std::string& cmd : cases) {
    SCOPED_TRACE(cmd);
    const auto r = run_qsp(cmd);
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("is an input file"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("name another output"), std::string::npos) << r.err;
  }
  for (const std::string& cmd :
       {"match " + quote(a) + " " + quote(b) + " -o " + quote(p("m.txt")) + " --faces " + quote(p("m.txt")),
        "match " + quote(a) + " " + quote(b) + " -o " + quote(p("m.txt")) + " --faces " +
            quote(p("sub/../m.txt"))}) {
    SCOPED_TRACE(cmd);
    const auto r = run_qsp(cmd);
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("would be written twice, for -o and for --faces"), std::string::npos) << r.err;
  }
  auto r = run_qsp("match " + quote(a) + " " + quote(b) + " -o - --faces -");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("standard output (-) is named twice, by -o and by --faces"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.obj", "b.obj", "hard_a.txt", "link_to_a.obj", "sub/"}));
  EXPECT_TRUE(fs::is_symlink(p("link_to_a.obj")));
  expect_inputs_unchanged();
  // Distinct outputs still work.
  r = run_qsp("match " + quote(a) + " " + quote(b) + " -o " + quote(p("m.txt")) + " --faces " +
              quote(p("f.txt")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(p("m.txt")) && fs::exists(p("f.txt")));
}

// show and layout read a mesh and write pictures and meshes: the same one check, and an existing output
// refused before any work with the way out named; layout's two outputs both checked before either is
// written.
TEST_F(CliFiles, ShowAndLayoutNeverWriteOverAnInput) {
  const std::string a = add("cube_4.obj", "a.obj");
  for (const std::string& cmd :
       {"layout -f " + quote(a) + " -o " + quote(a), "layout -f " + quote(a) + " --patches " + quote(a),
        "show -f " + quote(a) + " -o " + quote(p("sub/../a.obj"))}) {
    SCOPED_TRACE(cmd);
    const auto r = run_qsp(cmd);
    EXPECT_NE(r.exit_code, 0);
    if (cmd.rfind("show", 0) == 0) continue;  // show refuses a non-picture name first
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("is an input file"), std::string::npos) << r.err;
  }
  auto r = run_qsp("layout " + quote(a) + " -o " + quote(p("l.obj")) + " --patches " + quote(p("l.obj")));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("would be written twice, for -o and for --patches"), std::string::npos) << r.err;
  spit(p("p.ply"), "precious\n");
  r = run_qsp("layout " + quote(a) + " -o " + quote(p("l.obj")) + " --patches " + quote(p("p.ply")));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("p.ply: already exists; pass -f to replace it"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("l.obj")));  // neither written
  spit(p("x.png"), "precious\n");
  r = run_qsp("show " + quote(a) + " -o " + quote(p("x.png")));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("x.png: already exists; pass -f to replace it, or name another output"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(slurp(p("x.png")), "precious\n");
  // Standard input, with --format or by its magic, as everywhere.
  ASSERT_EQ(run_qsp("compress " + quote(a) + " " + quote(p("a.qsp"))).exit_code, 0);
  r = run_qsp("layout - --format obj -o " + quote(p("in.obj")) + " < " + quote(a));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run_qsp("layout - -o " + quote(p("in_qsp.obj")) + " < " + quote(p("a.qsp")));  // .qsp by its magic
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(slurp(p("in_qsp.obj")).find("stored partition"), std::string::npos);
  r = run_qsp("show - -o " + quote(p("in.png")) + " --size 64x64 < " + quote(a));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(slurp(p("in.png")).substr(1, 3), "PNG");
  expect_inputs_unchanged();
}

TEST_F(CliFiles, ForceOntoALinkWritesThroughIt) {
  const std::string a = add("cube_4.obj", "a.obj");
  spit(p("target.qsp"), "old\n");
  fs::create_symlink("target.qsp", p("link.qsp"));
  auto r = run_qsp("compress " + quote(a) + " " + quote(p("link.qsp")));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("link.qsp: already exists; pass -f to replace it"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(p("target.qsp")), "old\n");
  r = run_qsp("compress -f " + quote(a) + " " + quote(p("link.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("link.qsp is a symbolic link: writing through it to " +
                       fs::canonical(p("target.qsp")).string()),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::is_symlink(p("link.qsp")));
  EXPECT_TRUE(slurp(p("target.qsp")) == encoded(a));
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.obj", "link.qsp", "target.qsp"}));
  expect_inputs_unchanged();
}

// x.obj.qsp -> x.obj is the source mesh: never replaced without -f, and the refusal says the ways out.
TEST_F(CliFiles, DecompressDoesNotSilentlyReplaceTheSourceMesh) {
  const std::string a = add("cube_4.obj", "a.obj");
  ASSERT_EQ(run_qsp("compress " + quote(a)).exit_code, 0);
  inputs_["a.obj.qsp"] = slurp(p("a.obj.qsp"));
  auto r = run_qsp("decompress " + quote(p("a.obj.qsp")));
  EXPECT_EQ(r.exit_code, 3);
  for (const char* part :
       {"a.obj: already exists (perhaps the mesh", "pass -f", "-o NAME", "--output-dir", "-c"})
    EXPECT_NE(r.err.find(part), std::string::npos) << part << "\n" << r.err;
  expect_inputs_unchanged();
  r = run_qsp("decompress -f " + quote(p("a.obj.qsp")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(slurp(p("a.obj")) == decoded(inputs_["a.obj.qsp"]));
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.obj", "a.obj.qsp"}));
}

// The test: compress and decompress over a folder of good and bad files go on after each bad
// one, say one error per bad file, and exit non-zero at the end.
TEST_F(CliFiles, BatchOverAFolderOfGoodAndBadFiles) {
  std::vector<std::string> good = {add("cube_4.obj", "in/cube.obj"), add("l_shape.obj", "in/l.obj"),
                                   add("torus_twist_9x6_t2.obj", "in/torus.obj")};
  // (A triangle and a non-manifold edge are polygon meshes, which compress stores since format 3.1.)
  std::vector<std::string> bad = {add_bytes("in/b_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
                                  add_bytes("in/c_garbage.obj", "hello\n"),
                                  add_bytes("in/d_repeat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2 3\n")};
  fs::create_directory(p("in/folder.obj"));
  std::string all;
  for (const auto& e : fs::directory_iterator(p("in"))) all += " " + quote(e.path().string());
  auto r = run_qsp("compress" + all);
  EXPECT_EQ(r.exit_code, 1) << r.err;  // the first failure's code, a bad mesh
  for (const auto& g : good) EXPECT_TRUE(slurp(g + ".qsp") == encoded(g)) << g;
  for (const auto& f : bad) {
    EXPECT_NE(r.err.find("qsp: error: " + f + ":"), std::string::npos) << f << "\n" << r.err;
    EXPECT_FALSE(fs::exists(f + ".qsp")) << f;
  }
  EXPECT_NE(r.err.find(p("in/folder.obj") + ": is a folder"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 4) << r.err;  // one line per bad input
  expect_inputs_unchanged();

  // Decompress them all into another folder, with a corrupt .qsp among them.
  add_bytes("in/e_corrupt.qsp", "not a qsp at all");
  std::string packed;
  for (const auto& e : fs::directory_iterator(p("in")))
    if (format_from_path(e.path().string()) == MeshFormat::kQsp) packed += " " + quote(e.path().string());
  r = run_qsp("decompress --output-dir " + quote(p("out")) + packed);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("qsp: error: " + p("in/e_corrupt.qsp") + ": not a .qsp file"), std::string::npos)
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  for (const std::string name : {"cube.obj", "l.obj", "torus.obj"})
    EXPECT_TRUE(encoded(p("out/" + name)) == encoded(p("in/" + name))) << name;
  EXPECT_FALSE(fs::exists(p("out/e_corrupt.obj")));
  expect_inputs_unchanged();
}

TEST_F(CliFiles, StatsAndFingerprintGoOnAfterABadFile) {
  const std::string a = add("cube_4.obj", "a.obj"), b = add("l_shape.obj", "b.obj");
  const std::string bad = add_bytes("bad.obj", "v 0 0 0\nf 1 1 1 1\n");
  auto r = run_qsp("stats " + quote(a) + " " + quote(bad) + " " + quote(b));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find(a), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(b), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find(bad), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("qsp: error: " + bad + ":"), std::string::npos) << r.err;
  // JSON: always an array, the bad file an error object in its place.
  r = run_qsp("stats --json " + quote(a) + " " + quote(bad) + " " + quote(b));
  EXPECT_EQ(r.exit_code, 1);
  ASSERT_FALSE(r.out.empty());
  EXPECT_EQ(r.out.front(), '[');
  const std::size_t at_a = r.out.find("{\"file\": \"" + a + "\", \"partition\"");
  const std::size_t at_bad = r.out.find("{\"file\": \"" + bad + "\", \"error\": \"" + bad + ":");
  const std::size_t at_b = r.out.find("{\"file\": \"" + b + "\", \"partition\"");
  EXPECT_TRUE(at_a < at_bad && at_bad < at_b && at_b != std::string::npos) << r.out;
  r = run_qsp("stats --json " + quote(a));
  EXPECT_EQ(r.out.substr(0, 2), "[\n") << r.out;  // one file: still an array
  r = run_qsp("stats --json-lines " + quote(a) + " " + quote(bad));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 2) << r.out;
  EXPECT_EQ(r.out.front(), '{') << r.out;
  // fingerprint: a line per good file, in order, an error for the bad one.
  r = run_qsp("fingerprint " + quote(a) + " " + quote(bad) + " " + quote(b));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 2) << r.out;
  EXPECT_LT(r.out.find(a), r.out.find(b)) << r.out;
  EXPECT_NE(r.err.find("qsp: error: " + bad + ":"), std::string::npos) << r.err;
  r = run_qsp("fingerprint --group " + quote(a) + " " + quote(bad) + " " + quote(b));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find(b), std::string::npos) << r.out;
  expect_inputs_unchanged();
}

// --format on every subcommand that reads a mesh; OFF and PLY recognised on standard input.
TEST_F(CliFiles, StandardInputInAnyFormat) {
  const std::string a = add("cube_4.obj", "a.obj");
  ASSERT_EQ(run_qsp("compress " + quote(a) + " " + quote(p("a.qsp"))).exit_code, 0);
  ASSERT_EQ(run_qsp("decompress " + quote(p("a.qsp")) + " " + quote(p("a.off"))).exit_code, 0);
  const QuadMesh mesh = read_mesh_file(a);
  std::string ply = "ply\nformat ascii 1.0\n";
  for (const std::string& c : leading_comments(slurp(a))) ply += "comment " + c + "\n";  // kept as OBJ's are
  ply += "element vertex " + std::to_string(mesh.vertex_count()) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
         std::to_string(mesh.face_count()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    std::ostringstream line;
    line.precision(9);
    line << mesh.positions[3 * v] << " " << mesh.positions[3 * v + 1] << " " << mesh.positions[3 * v + 2]
         << "\n";
    ply += line.str();
  }
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    ply += "4 " + std::to_string(mesh.quads[4 * f]) + " " + std::to_string(mesh.quads[4 * f + 1]) + " " +
           std::to_string(mesh.quads[4 * f + 2]) + " " + std::to_string(mesh.quads[4 * f + 3]) + "\n";
  add_bytes("a.ply", ply);
  inputs_["a.off"] = slurp(p("a.off"));
  const std::string expected = encoded(a);
  for (const std::string src : {"a.obj", "a.off", "a.ply"}) {
    for (const std::string& format :
         {std::string(), " --format " + fs::path(src).extension().string().substr(1)}) {
      SCOPED_TRACE(src + format);
      auto r = run_qsp("compress -c -" + format + " < " + quote(p(src)));
      EXPECT_EQ(r.exit_code, 0) << r.err;
      EXPECT_TRUE(r.out == expected);
      r = run_qsp("fingerprint -" + format + " < " + quote(p(src)));
      EXPECT_EQ(r.exit_code, 0) << r.err;
      EXPECT_EQ(r.out.substr(0, 16), run_qsp("fingerprint " + quote(a)).out.substr(0, 16));
      r = run_qsp("stats -" + format + " < " + quote(p(src)));
      EXPECT_EQ(r.exit_code, 0) << r.err;
      EXPECT_NE(r.out.find("|       8      12       6 |"), std::string::npos) << r.out;
      r = run_qsp("match " + quote(a) + " -" + format + " < " + quote(p(src)));
      EXPECT_EQ(r.exit_code, 0) << r.err;
      r = run_qsp("reorder --like " + quote(a) + " - -o " + quote(p("r.obj")) + " -f" + format + " < " +
                  quote(p(src)));
      EXPECT_EQ(r.exit_code, 0) << r.err;
    }
  }
  // A .qsp on standard input: stats, fingerprint and match read it; compress says what it is.
  auto r = run_qsp("stats - < " + quote(p("a.qsp")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(leading_comments(slurp(a)).empty() ? "format 3.0" : "format 3.1"), std::string::npos)
      << r.out;
  r = run_qsp("compress -c - < " + quote(p("a.qsp")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("-: is .qsp compressed data, not a mesh (qsp decompress reads it)"), std::string::npos)
      << r.err;
  // By its name too, in the same words, before it is read.
  r = run_qsp("compress -c " + quote(p("a.qsp")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(p("a.qsp") + ": is .qsp compressed data, not a mesh (qsp decompress reads it)"),
            std::string::npos)
      << r.err;
  r = run_qsp("compress -c - --format stl < " + quote(a));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--format"), std::string::npos) << r.err;
  expect_inputs_unchanged();
}

TEST_F(CliFiles, MessagesNameTheWayOut) {
  const std::string a = add("cube_4.obj", "a.obj");
  fs::create_directory(p("meshes"));
  auto r = run_qsp("compress " + quote(p("meshes")));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find(p("meshes") + ": is a folder, not a mesh file (give the files in it, e.g. " +
                       p("meshes") + "/*.obj)"),
            std::string::npos)
      << r.err;
  for (const char* cmd : {"stats", "fingerprint"}) {
    r = run_qsp(std::string(cmd) + " " + quote(p("meshes")));
    EXPECT_NE(r.err.find("is a folder"), std::string::npos) << cmd << r.err;
  }
  r = run_qsp("compres " + quote(a));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("'compres' is not a subcommand; did you mean compress?"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("A subcommand is required"), std::string::npos) << r.err;
  r = run_qsp("compress --forse " + quote(a));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--forse is not an option of qsp compress; did you mean --force?"), std::string::npos)
      << r.err;
  r = run_qsp("stats --jsn " + quote(a));
  EXPECT_NE(r.err.find("did you mean --json?"), std::string::npos) << r.err;
  // Weights and colours compress keeps, so a file where one vertex has one is refused at that vertex's
  // line (tests/test_cli_drop.cpp has the refusals that name a --drop).
  const std::string normal = add_bytes("normal.obj", slurp(a) + "v 0 0 0 1\n");  // a vertex weight
  r = run_qsp("compress " + quote(normal));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("normal.obj:197: `v` has 4 numbers but the first vertex (line 3) has 3"),
            std::string::npos)
      << r.err;
  const std::string one = add_bytes("one.obj", slurp(a) + "v 0 0 0 1 0 0\n");
  r = run_qsp("compress " + quote(one));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("one.obj:197: `v` has 6 numbers but the first vertex (line 3) has 3"),
            std::string::npos)
      << r.err;
  // reorder and match name the files, not A and B.
  const std::string two = add("multi_component.obj", "two.obj");
  r = run_qsp("reorder --like " + quote(a) + " " + quote(two) + " -o " + quote(p("out.obj")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(a + " has 1, " + two + " has 4"), std::string::npos) << r.err;
  r = run_qsp("match " + quote(two) + " " + quote(a));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find(two + " has 4, " + a + " has 1"), std::string::npos) << r.out;
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.obj", "meshes/", "normal.obj", "one.obj", "two.obj"}));
  expect_inputs_unchanged();
}

TEST_F(CliFiles, VerboseQuietAndTheQuantizeWarning) {
  const std::string a = add("cube_4.obj", "a.obj");
  auto r = run_qsp("compress -v " + quote(a));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string size = std::to_string(fs::file_size(p("a.obj.qsp")));
  for (const std::string& part : std::vector<std::string>{
           a + " -> " + a + ".qsp: " + std::to_string(inputs_["a.obj"].size()) + " -> " + size + " bytes",
           "x smaller", "bits/vertex", "lossless", " (auto), ", " s\n"})
    EXPECT_NE(r.err.find(part), std::string::npos) << part << "\n" << r.err;
  // The partition auto chose: that mode's file is the same bytes.
  const std::size_t at = r.err.find("partition "), end = r.err.find(" (auto)");
  ASSERT_TRUE(at != std::string::npos && end != std::string::npos) << r.err;
  const std::string mode = r.err.substr(at + 10, end - at - 10);
  ASSERT_EQ(
      run_qsp("compress -f --partition " + mode + " " + quote(a) + " " + quote(p("mode.qsp"))).exit_code, 0)
      << mode;
  EXPECT_TRUE(slurp(p("mode.qsp")) == slurp(p("a.obj.qsp"))) << mode;
  fs::remove(p("mode.qsp"));
  // cube_4's integer positions cost less losslessly than on any grid: say so, with the lossless size.
  r = run_qsp("compress -f --quantize 14 " + quote(a));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("not smaller than lossless (" + size + " bytes)"), std::string::npos) << r.err;
  r = run_qsp("compress -f -q --quantize 14 " + quote(a));
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.err, "");
  // The same cube in millimetres far from the origin (2 decimals on values near 1000, which a float holds
  // only as the nearest to each): lossless still wins, and the check still runs without -v.
  std::string mm;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j)
      mm += "v " + std::to_string(1000.37 + 10 * i).substr(0, 7) + " " +
            std::to_string(2000.41 + 10 * j).substr(0, 7) + " 1500.13\n";
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const int c = 5 * i + j + 1;
      mm += "f " + std::to_string(c) + " " + std::to_string(c + 5) + " " + std::to_string(c + 6) + " " +
            std::to_string(c + 1) + "\n";
    }
  testing::spit(p("mm.obj"), mm);
  r = run_qsp("compress -f --quantize 14 " + quote(p("mm.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("not smaller than lossless"), std::string::npos) << mm << r.err;
  r = run_qsp("decompress -v -f " + quote(p("a.obj.qsp")) + " -o " + quote(p("b.obj")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("98 vertices, 96 faces, quantized 14 bits, canonical order"), std::string::npos)
      << r.err;
  // An empty mesh is written, with a warning.
  const std::string empty = add_bytes("empty.obj", "# nothing\n");
  r = run_qsp("compress " + quote(empty));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + empty + ": has no faces"), std::string::npos) << r.err;
  expect_inputs_unchanged();
}

}  // namespace
}  // namespace qsp
