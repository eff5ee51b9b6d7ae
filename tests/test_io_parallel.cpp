// read_obj's two-thread read against the sequential one: for every OBJ in the corpus, crafted texts
// and mutants, split at every line start (or many), mesh, report and error must be the same.
#include <gtest/gtest.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "io_text.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"
#include "support/corpus.h"
#include "support/files.h"
#include "support/mesh_compare.h"

namespace fs = std::filesystem;
using qsp::testing::slurp;

namespace {

using Splits = std::vector<std::size_t>;
const Splits kSequential;

// What a read gave: a mesh and report, or an error (with the report as the error left it).
struct Outcome {
  bool ok = false;
  std::vector<std::uint32_t> position_bits;
  std::vector<std::uint32_t> quads;
  qsp::ReadReport report;
  qsp::ErrorCode code{};
  std::string message;
};

Outcome read(std::string_view text, const Splits& splits, bool* parallel = nullptr) {
  Outcome out;
  out.report.texcoords = 99;  // the read must reset what it reports
  try {
    const qsp::QuadMesh m = qsp::detail::read_obj_split(text, "t.obj", &out.report, splits, parallel);
    out.ok = true;
    out.position_bits.resize(m.positions.size());
    std::memcpy(out.position_bits.data(), m.positions.data(), 4 * m.positions.size());
    out.quads = m.quads;
  } catch (const qsp::Error& e) {
    out.code = e.code();
    out.message = e.what();
  }
  return out;
}

void expect_same(const Outcome& want, const Outcome& got) {
  ASSERT_EQ(want.ok, got.ok) << (want.ok ? got.message : want.message);
  EXPECT_EQ(qsp::error_name(want.code), std::string(qsp::error_name(got.code)));
  EXPECT_EQ(want.message, got.message);
  EXPECT_EQ(want.position_bits, got.position_bits);
  EXPECT_EQ(want.quads, got.quads);
  const qsp::ReadReport &a = want.report, &b = got.report;
  EXPECT_EQ(a.texcoords, b.texcoords);
  EXPECT_EQ(a.faces_with_texcoords, b.faces_with_texcoords);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.faces_with_normals, b.faces_with_normals);
  EXPECT_EQ(a.groups, b.groups);
  EXPECT_EQ(a.materials, b.materials);
  EXPECT_EQ(a.smoothing, b.smoothing);
  EXPECT_EQ(a.tags, b.tags);
  EXPECT_EQ(a.vertex_colors, b.vertex_colors);
  EXPECT_EQ(a.face_colors, b.face_colors);
  EXPECT_EQ(a.vertex_weights, b.vertex_weights);
  EXPECT_EQ(a.kept_lines, b.kept_lines);
  EXPECT_EQ(a.first_kept.line, b.first_kept.line);
  EXPECT_EQ(a.first_kept.message, b.first_kept.message);
  EXPECT_EQ(a.other_properties, b.other_properties);
  EXPECT_EQ(a.obj_info, b.obj_info);
  EXPECT_EQ(a.face_line, b.face_line);
  EXPECT_EQ(a.rounded_coordinates, b.rounded_coordinates);
  EXPECT_EQ(a.first_rounded.line, b.first_rounded.line);
  EXPECT_EQ(a.first_rounded.vertex, b.first_rounded.vertex);
  EXPECT_EQ(a.first_rounded.value, b.first_rounded.value);
}

// Every split point of `text`, in order.
Splits split_points(std::string_view text) {
  Splits out;
  for (std::size_t s = qsp::detail::obj_split_point(text, 0); s != std::string_view::npos;
       s = qsp::detail::obj_split_point(text, s)) {
    out.push_back(s);
  }
  return out;
}

// At most `most` of `all`, spread evenly.
Splits spread(const Splits& all, std::size_t most) {
  if (all.size() <= most) return all;
  Splits out;
  for (std::size_t i = 0; i < most; ++i) out.push_back(all[i * all.size() / most]);
  return out;
}

// How many split reads a check made and how many of them used the two-thread result.
struct Checked {
  std::size_t reads = 0, parallel = 0;
};

// The splits to compare with the sequential read: each single one (spread, at most `max_halves`),
// all of them (at most 256), and `subsets` random subsets.
std::vector<Splits> split_cases(std::string_view text, std::size_t max_halves, int subsets) {
  const Splits all = split_points(text);
  std::vector<Splits> cases;
  for (const std::size_t s : spread(all, max_halves)) cases.push_back({s});
  if (all.size() > 1) cases.push_back(spread(all, 256));
  std::mt19937 rng(static_cast<unsigned>(text.size()));
  for (int i = 0; i < subsets && all.size() > 2; ++i) {
    Splits some;
    for (const std::size_t s : all) {
      if (rng() % 4 == 0) some.push_back(s);
    }
    if (!some.empty()) cases.push_back(some);
  }
  return cases;
}

// Reads `text` with `read(text, splits, &parallel)` at each of split_cases against the sequential
// read, compared by expect_same.
template <class Read>
Checked check_splits_with(std::string_view text, std::size_t max_halves, int subsets, Read read) {
  const auto want = read(text, kSequential, nullptr);
  const bool failed_before = ::testing::Test::HasFailure();
  Checked checked;
  for (const Splits& splits : split_cases(text, max_halves, subsets)) {
    std::ostringstream where;
    where << "split at";
    for (std::size_t i = 0; i < splits.size() && i < 16; ++i) where << ' ' << splits[i];
    if (splits.size() > 16) where << " ...";
    SCOPED_TRACE(where.str());
    bool parallel = false;
    expect_same(want, read(text, splits, &parallel));
    if (!failed_before && ::testing::Test::HasFailure()) break;  // one report is enough
    ++checked.reads;
    checked.parallel += parallel;
  }
  return checked;
}

// read_obj split in two at each split point (at most `max_halves`), in parts at every split point,
// and at `subsets` random subsets of them, against the sequential read.
Checked check_splits(std::string_view text, std::size_t max_halves = std::string_view::npos,
                     int subsets = 8) {
  return check_splits_with(text, max_halves, subsets,
                           [](std::string_view t, const Splits& s, bool* p) { return read(t, s, p); });
}

const std::string kSquare = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

}  // namespace

TEST(ReadObjParallel, SplitPointsAreLineStartsOutsideContinuations) {
  using qsp::detail::obj_split_point;
  EXPECT_EQ(obj_split_point("v 1 2 3\nv 4 5 6\n", 0), 8u);
  EXPECT_EQ(obj_split_point("v 1 2 3\nv 4 5 6\n", 8), std::string_view::npos);  // nothing after the last LF
  EXPECT_EQ(obj_split_point("v 1 2 3\r\nv 4 5 6", 0), 9u);
  EXPECT_EQ(obj_split_point("v 1 2 3\rv 4 5 6\n", 0), std::string_view::npos);  // a lone CR is never a split
  EXPECT_EQ(obj_split_point("v 1 \\\n2 3\nv 4 5 6", 0), 10u);
  EXPECT_EQ(obj_split_point("v 1 \\ \t\r\n2 3\nv 4 5 6", 0), 13u);
  EXPECT_EQ(obj_split_point("v 1 2 3\\\nv", 0), std::string_view::npos);
  EXPECT_EQ(obj_split_point("\n\nv", 1), 2u);
}

TEST(ReadObjParallel, LargeInputsAreReadOnTwoThreadsAndSmallOnesAreNot) {
  std::string text = kSquare;
  for (int i = 0; text.size() < qsp::detail::kParallelObjBytes; ++i) {
    text += "v " + std::to_string(i) + " 0.5 -1e-3\nf -5 -4 -3 -2\n";
  }
  const Outcome want = read(text, kSequential);
  ASSERT_TRUE(want.ok) << want.message;
  Outcome got;
  got.ok = true;
  got.report.texcoords = 7;
  const qsp::QuadMesh m = qsp::read_obj(text, "t.obj", &got.report);
  got.position_bits.resize(m.positions.size());
  std::memcpy(got.position_bits.data(), m.positions.data(), 4 * m.positions.size());
  got.quads = m.quads;
  expect_same(want, got);
  // read_obj's splits are taken on two threads.
  const Splits splits = qsp::detail::obj_read_splits(text);
  EXPECT_EQ(splits.size(), qsp::detail::kParallelObjParts - 1);
  bool parallel = false;
  expect_same(want, read(text, splits, &parallel));
  EXPECT_TRUE(parallel);
  // Below the threshold read_obj reads sequentially.
  text.resize(qsp::detail::obj_split_point(text, qsp::detail::kParallelObjBytes - 100));
  ASSERT_LT(text.size(), qsp::detail::kParallelObjBytes);
  EXPECT_TRUE(qsp::detail::obj_read_splits(text).empty());
}

TEST(ReadObjParallel, EveryCorpusObjReadsTheSameAtManySplits) {
  int files = 0;
  for (const fs::path& p : qsp::testing::corpus()) {
    if (p.extension() != ".obj") continue;
    SCOPED_TRACE(p.string());
    const std::string text = slurp(p);
    const Outcome want = read(text, kSequential);
    // The reader alone refuses only what is not a quad mesh; topology defects are build_adjacency's.
    if (qsp::testing::expected_valid(p)) {
      EXPECT_TRUE(want.ok) << want.message;
    }
    const bool large = text.size() >= (1 << 20);
    const Checked checked = check_splits(text, text.size() < 4096 ? 1000 : large ? 2 : 16, large ? 1 : 8);
    // Valid files, and those refused for non-quads, take the two-thread result however they are split.
    if (want.ok || want.code == qsp::ErrorCode::kNotQuad) {
      EXPECT_EQ(checked.parallel, checked.reads);
    }
    ++files;
  }
  const auto all = qsp::testing::corpus();
  EXPECT_EQ(files,
            std::count_if(all.begin(), all.end(), [](const fs::path& p) { return p.extension() == ".obj"; }));
}

TEST(ReadObjParallel, EveryInvalidObjFailsTheSameAtEverySplit) {
  int files = 0;
  for (const fs::path& p : qsp::testing::invalid_meshes()) {
    if (p.extension() != ".obj") continue;
    SCOPED_TRACE(p.string());
    (void)check_splits(slurp(p), 200);  // topology/ files may read fine: only build_adjacency refuses them
    ++files;
  }
  EXPECT_GE(files, 20);
}

TEST(ReadObjParallel, CraftedTextsReadTheSameAtEverySplit) {
  const std::string square2 = "v 2 0 0\nv 2 1 0\nv 3 0 0\nv 3 1 0\n";
  struct Case {
    const char* name;
    std::string text;
    bool valid;
  };
  const std::vector<Case> cases = {
      {"relative indices across the split",
       kSquare + "f -4 -3 -2 -1\n" + square2 +
           "f -4 -3 -2 -1\nf -8 -7 -6 -5\nf 1 -7 3 -1\nf -1/1/1 -2//1 2 1\n",
       true},
      {"relative and absolute corners that differ", kSquare + square2 + "f 5 -3 -2 -1\nf -8 6 -1 -2\n", true},
      {"relative index reaching before the file",
       kSquare + "f 1 2 3 4\n" + square2 + "f -4 -3 -2 -1\nf -9 -3 -2 -1\n", false},
      {"relative index repeating an absolute one", kSquare + square2 + "f 1 2 3 4\nf 8 -3 -2 -1\n", false},
      {"relative indices repeating each other", kSquare + square2 + "f 1 2 3 4\nf -1 -3 -2 -1\n", false},
      {"coordinates float32 does not keep, in both halves",
       kSquare + "v 0.1234567891 0 0\nf 1 2 3 4\n" + square2 +
           "v 1 2.00000001 3\nv 7 8 9.87654321012\nf 5 6 7 8\n",
       true},
      {"forward references", "f 1 2 3 4\nf 5 6 7 8\n" + kSquare + "f 1 2 3 4\n" + square2, true},
      {"forward reference beyond the file", "f 1 2 3 9\n" + kSquare + "f 1 2 3 4\n" + square2, false},
      {"forward reference beyond the file, late",
       kSquare + "f 1 2 3 4\n" + square2 + "f 5 6 7 8\nf 1 2 3 9\n", false},
      {"errors in both halves: the first wins",
       kSquare + "v 1 2 x\nf 1 2 3 4\n" + square2 + "f 1 2 3 4\nv 1 2 y\nf 1 1 2 3\n", false},
      {"error late only", kSquare + "f 1 2 3 4\n" + square2 + "f 1 2 3 4\nusemtl a\nl 1 2\n", false},
      {"error early only", kSquare + "v 1 2\nf 1 2 3 4\n" + square2 + "f 1 2 3 4\nf 5 6 7 8\n", false},
      {"lines kept as text on both sides",
       kSquare + "This line is prose\nf 1 2 3 4\n" + square2 + "f 1 2 3 4\ncstype bspline\nq 1\n", true},
      {"lines kept as text late only", kSquare + "f 1 2 3 4\n" + square2 + "f 5 6 7 8\nvp 0.5\nt crease 1\n",
       true},
      {"non-quads in both halves",
       kSquare + "f 1 2 3\nf 1 2 3 4\nf 1 2 3 4 2\n" + square2 + "f 1 2\nf\nf 5 6 7 8\nf 4 3 2\n", false},
      {"non-quads early, a parse error late",
       kSquare + "f 1 2 3\nf 1 2 3 4\n" + square2 + "f 1 2 3 4\nv 1 2\n", false},
      {"non-quad late, a bad index early", kSquare + "f 0 2 3 4\nf 1 2 3 4\n" + square2 + "f 1 2 3\n", false},
      {"non-quad early, a repeat late", kSquare + "f 1 2 3\n" + square2 + "f 1 2 3 4\nf 5 6 5 8\n", false},
      {"CRLF", "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\n\r\nv 0 1 0\r\nf 1 2 3 4\r\nf -1 -2 -3 -4\r\n", true},
      {"lone CRs", "v 0 0 0\rv 1 0 0\nv 1 1 0\r\rv 0 1 0\r\nf 1 2 3 4\rf -1 -2 -3 -4\n# c\rf 2 3 4 1\n",
       true},
      {"continuations",
       "v 0 0 \\\n0\nv 1 0 0 \\ \r\n\nv 1 1 0\\\r\n\nv 0 1 0\n\nf 1 2 \\\n3 4\nf -1 \\\n-2 -3 -4\n", true},
      {"continuation before a lone CR", "v 0 0 \\\r0\nv 1 0 0\nv 1 1 0 \\ \r \nv 0 1 0\nf 1 2 3 4\n", true},
      {"a backslash in a comment", "# dir\\\nv 0 0 0\nv 1 0 0\n# a \\ b \\\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n",
       true},
      {"a continuation into an error", kSquare + "f 1 2 3 \\\n4 x\nf 1 2 3 4\n", false},
      {"comments and blank lines", "# a\n\n  \t\n" + kSquare + "# b\nf 1 2 3 4 # c\n\n#\n", true},
      {"no line end at the end", kSquare + "f 1 2 3 4\nf 4 3 2 1", true},
      {"error without a line end at the end", kSquare + "f 1 2 3 4\nf 4 3 2", false},
      {"extras on both sides",
       "mtllib m\no a\n" + kSquare +
           "v 1 2 3 0.5 0.5 0.5\nvt 0 0\nvn 0 0 1\nvp 0.5\ng g\ns 1\nusemtl x\n"
           "f 1/1 2/1 3/1 4/1\nt crease 2/1/0 1 2 4.0\nv 4 5 6 1\nvt 1 1\nvn 1 0 0\n"
           "o b\ns off\nf 2//1 5//1 3//1 1//1\nusemap u\nmaplib l\n",
       true},
      {"a byte order mark at the start", "\xEF\xBB\xBF" + kSquare + "f 1 2 3 4\n", true},
      {"a byte order mark mid-file: a line kept as text", kSquare + "\xEF\xBB\xBFv 1 2 3\nf 1 2 3 4\n", true},
      {"free-form geometry late", kSquare + "f 1 2 3 4\ncstype bspline\ncurv 0 1 1 2\n", false},
      {"malformed numbers", kSquare + "v 1e99 0 0\nf 1 2 3 4\n", false},
      {"a vertex reference with junk", kSquare + "f 1/2/3/4 2 3 4\n", false},
      {"trailing junk", kSquare + "f 1 2 3 4 \\ x\nf 1 2 3 4\n", false},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Outcome want = read(c.text, kSequential);
    EXPECT_EQ(want.ok, c.valid) << want.message;
    const Checked checked = check_splits(c.text);
    if (want.ok || want.code == qsp::ErrorCode::kNotQuad) {
      EXPECT_EQ(checked.parallel, checked.reads);
    }
  }
}

TEST(ReadObjParallel, MutantsReadTheSameAtEverySplit) {
  // Byte and line edits of a small valid file: whatever the sequential read makes of them (often an
  // error), the split read must make the same.
  const std::string base =
      "# m\n" + kSquare + "v 2 0 0\nv 2 1 0\r\nf 1 2 3 4\nf -4 -1 -2 3\ng x\nf 2 5 6 3\nv 3 3 3\n";
  const std::string alphabet = "vf t#/\\-+.0123456789e\n\r\n\nx";
  std::mt19937 rng(2024);
  const auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  int valid = 0;
  for (int round = 0; round < 400; ++round) {
    std::string text = base;
    for (int e = 1 + static_cast<int>(pick(2)); e > 0 && !text.empty(); --e) {
      const std::size_t at = pick(text.size());
      const char c = alphabet[pick(alphabet.size())];
      std::size_t start = text.rfind('\n', at);
      start = start == std::string::npos ? 0 : start + 1;
      std::size_t end = text.find('\n', at);
      end = end == std::string::npos ? text.size() : end + 1;
      const std::string line = text.substr(start, end - start);
      switch (pick(6)) {
        case 0:
          text[at] = c;
          break;
        case 1:
          text.insert(at, 1, c);
          break;
        case 2:
          text.erase(at, 1);
          break;
        case 3:  // another digit: often still valid
          if (text[at] >= '0' && text[at] <= '9') text[at] = static_cast<char>('0' + pick(10));
          break;
        case 4:
          text.insert(start, line);
          break;
        default:
          text.erase(start, end - start);
      }
    }
    SCOPED_TRACE("mutant " + std::to_string(round) + ": " + text);
    valid += read(text, kSequential).ok;
    (void)check_splits(text);
    if (HasFailure()) return;
  }
  EXPECT_GE(valid, 40);  // enough mutants stay valid that the success path is compared too
}

// write_obj and write_off format the second half of a large mesh's vertices on a second thread. The
// text must be exactly what one thread writes: every float in its shortest round-trip form, in order.
TEST(WriteTextParallel, LargeMeshesGiveTheSingleThreadedText) {
  std::mt19937 rng(11);
  for (const std::size_t n : {std::size_t{65535}, std::size_t{65536}, std::size_t{100001}}) {
    SCOPED_TRACE(n);
    qsp::QuadMesh m;
    m.positions.resize(3 * n);
    for (float& f : m.positions) {
      std::uint32_t bits = rng();
      while ((bits & 0x7F800000u) == 0x7F800000u) bits = rng();  // finite only
      std::memcpy(&f, &bits, 4);
    }
    for (std::uint32_t q = 0; q + 3 < n; q += 4) m.quads.insert(m.quads.end(), {q, q + 1, q + 2, q + 3});
    // The expected text: each vertex's coordinates in their shortest form (OBJ adds "v " in front).
    std::string v, xyz, f;
    char buf[32];
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      if (i % 3 == 0) v += "v ";
      const std::string_view text(buf, std::to_chars(buf, buf + sizeof buf, m.positions[i]).ptr);
      const char sep = i % 3 == 2 ? '\n' : ' ';
      (v += text) += sep;
      (xyz += text) += sep;
    }
    for (std::size_t i = 0; i < m.quads.size(); i += 4) {
      f += "f " + std::to_string(m.quads[i] + 1) + ' ' + std::to_string(m.quads[i + 1] + 1) + ' ' +
           std::to_string(m.quads[i + 2] + 1) + ' ' + std::to_string(m.quads[i + 3] + 1) + '\n';
    }
    // (Compared by hand: a failing EXPECT_EQ would print megabytes.)
    const auto first_difference = [](const std::string& a, const std::string& b) {
      return std::mismatch(a.begin(), a.end(), b.begin(), b.end()).first - a.begin();
    };
    const std::string obj = qsp::write_obj(m), want = v + f;
    EXPECT_TRUE(obj == want) << "write_obj differs at byte " << first_difference(obj, want);
    const std::string off = qsp::write_off(m);
    const std::string head = "OFF\n" + std::to_string(n) + ' ' + std::to_string(m.quads.size() / 4) + " 0\n";
    ASSERT_GE(off.size(), head.size() + xyz.size());
    const std::string got = off.substr(0, head.size() + xyz.size());
    EXPECT_TRUE(got == head + xyz) << "write_off differs at byte " << first_difference(got, head + xyz);
  }
}

// ---------------------------------------------------------------------------------------------
// The exact reader (read_obj_mesh): the same guarantees, over the whole model.

namespace {

struct MeshOutcome {
  bool ok = false;
  qsp::Mesh mesh;
  qsp::ReadNotes notes;
  std::string message;
};

MeshOutcome read_mesh(std::string_view text, const Splits& splits, bool* parallel = nullptr) {
  MeshOutcome out;
  try {
    out.mesh = qsp::detail::read_obj_mesh_split(text, "t.obj", &out.notes, splits, parallel);
    out.ok = true;
  } catch (const qsp::Error& e) {
    out.message = std::string(qsp::error_name(e.code())) + ": " + e.what();
  }
  return out;
}

void expect_same(const MeshOutcome& want, const MeshOutcome& got) {
  ASSERT_EQ(want.ok, got.ok) << (want.ok ? got.message : want.message);
  EXPECT_EQ(want.message, got.message);
  if (!want.ok) return;
  qsp::testing::expect_same_mesh(want.mesh, got.mesh);
  EXPECT_EQ(want.notes.face_line, got.notes.face_line);
  EXPECT_EQ(want.notes.warning_count, got.notes.warning_count);
  EXPECT_EQ(want.notes.describe_warnings("t.obj"), got.notes.describe_warnings("t.obj"));
}

// As check_splits, for the exact reader.
Checked check_mesh_splits(std::string_view text, std::size_t max_halves = std::string_view::npos) {
  return check_splits_with(text, max_halves, 8,
                           [](std::string_view t, const Splits& s, bool* p) { return read_mesh(t, s, p); });
}

}  // namespace

TEST(ReadObjMeshParallel, EveryCorpusObjReadsTheSameAtManySplits) {
  int files = 0;
  for (const fs::path& p : qsp::testing::corpus()) {
    if (p.extension() != ".obj") continue;
    SCOPED_TRACE(p.string());
    const std::string text = slurp(p);
    const MeshOutcome want = read_mesh(text, kSequential);
    const bool large = text.size() >= (1 << 20);
    const Checked checked = check_mesh_splits(text, text.size() < 4096 ? 1000 : large ? 2 : 16);
    // Every file the reader accepts takes the two-thread result however it is split.
    if (want.ok) {
      EXPECT_EQ(checked.parallel, checked.reads);
    }
    ++files;
  }
  // Without ../shared the corpus is testdata's OBJ files alone (the sentinel test fails that under CI).
  EXPECT_GT(files, qsp::testing::shared_present() ? 100 : 20);
}

TEST(ReadObjMeshParallel, CraftedTextsReadTheSameAtEverySplit) {
  const std::string square2 = "v 2 0 0\nv 2 1 0\nv 3 0 0\nv 3 1 0\n";
  const std::vector<std::pair<const char*, std::string>> cases = {
      {"labels across the split",
       "# licence\nmtllib m.mtl\no a\n" + kSquare + "g x y\nusemtl red\ns 1\nf 1 2 3 4\n" + square2 +
           "f 5 6 7 8\nusemtl blue\nf 1 2 3\ng z\ns off\nf 2 3 4\no b\nusemtl red\nf 4 3 2 1\n"},
      {"labels only late", kSquare + "f 1 2 3 4\n" + square2 + "f 5 6 7\ng late\nf 6 7 8\n"},
      {"relative texture coordinates and normals",
       kSquare + "vt 0 0\nvt 1 0\nvn 0 0 1\nf -4/-2/-1 -3/-1/-1 -2/-2/-1\n" + square2 +
           "vt 0.5 0.5\nvn 1 0 0\nf -4/-1/-1 -3/-2/-2 -2/1/1 -1//-1\n"},
      {"texture coordinates of different lengths",
       "vt 0.5\n" + kSquare + "vt 1 2 3\nf 1/1 2/2 3/1\n" + square2 + "vt 4\n"},
      {"vertex colours", "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nf 1 2 3\nv 0 1 0 1 1 1\nf 1 3 4\n"},
      {"vertex colours disagreeing late",
       "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nf 1 2 3\nv 0 1 0\nf 1 3 4\n"},
      {"tags and kept lines", kSquare + "f 1 2 3 4\nThis is prose\n" + square2 +
                                  "vp 0.1\nt crease 2/1/0 0 7 3\nt hole 1/0/0 0\ncstype bspline\n"},
      {"a tag index beyond the file", kSquare + "f 1 2 3 4\n" + square2 + "t corner 1/1/0 8 3\n"},
      {"a forward texture coordinate beyond the file",
       kSquare + "f 1/3 2/1 3/2\n" + square2 + "vt 0 0\nvt 1 1\n"},
      {"n-gons and a repeat late", kSquare + square2 + "f 1 2 3 4 5 6\nf 1 2 3\nf -1 -2 -1\n"},
      {"many decimals",
       "v 0.1234567890123 1e39 0.1\n" + kSquare + "v 0.123456789012345678901 0 0\nf 1 2 3\n"},
  };
  for (const auto& [name, text] : cases) {
    SCOPED_TRACE(name);
    const MeshOutcome want = read_mesh(text, kSequential);
    const Checked checked = check_mesh_splits(text);
    if (want.ok) {
      EXPECT_EQ(checked.parallel, checked.reads);
    }
  }
}

TEST(ReadObjMeshParallel, LargeInputsAreReadOnTwoThreads) {
  std::string text = "# big\n" + kSquare;
  for (int i = 0; text.size() < qsp::detail::kParallelObjBytes; ++i) {
    text += "v " + std::to_string(i) + " 0.5 -1e-3 0 0.5 1\nvt 0.5 " + std::to_string(i % 7) +
            "\nf -5/-1 -4/-1 -3/-1 -2/-1\n";
    if (i % 1000 == 0) text += "g part" + std::to_string(i / 1000) + "\n";
  }
  text.replace(text.find("v 0 0 0\n"), 8, "v 0 0 0 1 1 1\n");
  text.replace(text.find("v 1 0 0\n"), 8, "v 1 0 0 1 1 1\n");
  text.replace(text.find("v 1 1 0\n"), 8, "v 1 1 0 1 1 1\n");
  text.replace(text.find("v 0 1 0\n"), 8, "v 0 1 0 1 1 1\n");
  const MeshOutcome want = read_mesh(text, kSequential);
  ASSERT_TRUE(want.ok) << want.message;
  bool parallel = false;
  expect_same(want, read_mesh(text, qsp::detail::obj_read_splits(text), &parallel));
  EXPECT_TRUE(parallel);
}

namespace {

// `text` with a tab for every space between the items of its `v`, `vt`, `vn` and `f` lines: the same
// statements, which the readers' fast path for plain lines leaves to the general one.
std::string tabbed(std::string_view text) {
  std::string out(text);
  std::size_t line = 0;
  while (line < out.size()) {
    const std::size_t end = std::min(out.find('\n', line), out.size());
    const std::string_view l = std::string_view(out).substr(line, end - line);
    if (l.starts_with("v ") || l.starts_with("vt ") || l.starts_with("vn ") || l.starts_with("f ")) {
      std::replace(out.begin() + static_cast<std::ptrdiff_t>(line),
                   out.begin() + static_cast<std::ptrdiff_t>(end), ' ', '\t');
    }
    line = end + 1;
  }
  return out;
}

}  // namespace

// The fast path for plain lines reads what the general path reads: mesh, report, warnings and errors,
// in both modes, on every corpus OBJ and on lines at the edges of what the fast path takes.
TEST(ReadObjFastPath, PlainLinesReadAsTheGeneralPathReadsThem) {
  const auto check = [](std::string_view text) {
    const std::string slow = tabbed(text);
    expect_same(read(slow, kSequential), read(text, kSequential));
    expect_same(read_mesh(slow, kSequential), read_mesh(text, kSequential));
  };
  int files = 0;
  for (const fs::path& p : qsp::testing::corpus()) {
    if (p.extension() != ".obj") continue;
    SCOPED_TRACE(p.string());
    check(slurp(p));
    ++files;
  }
  EXPECT_GT(files, qsp::testing::shared_present() ? 100 : 20);
  const std::vector<std::string> lines = {"v 0.5 -0.25 1e2\n",
                                          "v -0 0.0000001 16777217\n",
                                          "v 0.123456789 1.5 2\n",
                                          "v 1.5 2 3 4\n",
                                          "v 1 2\n",
                                          "v 1 2 3 \n",
                                          "v +1 2 3\n",
                                          "v 1e39 1 1\n",
                                          "v 1e-50 1 1\n",
                                          "v nan 1 1\n",
                                          "v 1 2 3 # c\n",
                                          "v 12345678901234567890123 1 1\n",
                                          "v .5 -.5 5.\n",
                                          "v 0.1000000000000000055511151231257827 1 1\n",
                                          "vt 0.25\n",
                                          "vt 0.25 0.5\n",
                                          "vt 0.25 0.5 0.75\n",
                                          "vt 1 2 3 4\n",
                                          "vt\n",
                                          "vt 1e40 0\n",
                                          "vt 0.5 x\n",
                                          "vn 0 0 1\n",
                                          "vn 0 1\n",
                                          "vn 0 0 1 1\n",
                                          "vn 0.577 0.577 0.577\n",
                                          "f 1 2 3 4\n",
                                          "f 1/1 2/2 3/3 4/4\n",
                                          "f 1//1 2//1 3//1 4//1\n",
                                          "f 1/1/1 2/2/1 3/3/1 4/4/1\n",
                                          "f 1/1 2 3/3 4\n",
                                          "f 1 2 3\n",
                                          "f 1/1 2/2 3/3\n",
                                          "f 1 2 3 4 1\n",
                                          "f 1 2 3 4 5 6 7 8 1 2\n",
                                          "f 0 1 2 3\n",
                                          "f 1/0 2/1 3/1 4/1\n",
                                          "f 1/ 2/ 3/ 4/\n",
                                          "f 1// 2// 3// 4//\n",
                                          "f 1/1/ 2/1/ 3/1/ 4/1/\n",
                                          "f 1/1/1/1 2 3 4\n",
                                          "f 1 2 3 4 \n",
                                          "f -1 -2 -3 -4\n",
                                          "f 1/-1 2/-1 3/-1 4/-1\n",
                                          "f 1 1 2 3\n",
                                          "f 9999999999 1 2 3\n",
                                          "f 1/9999999999 2/1 3/1 4/1\n",
                                          "f 1/1 2/2 3/3 4/4 # c\n",
                                          "f 1 2 3 4",
                                          "g a\n",
                                          "usemtl m\n",
                                          "s 1\n",
                                          "# c\n",
                                          "\n"};
  std::mt19937 rng(19);
  const std::string square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n";
  for (int i = 0; i < 3000; ++i) {
    std::string text = square;
    const int n = 1 + static_cast<int>(rng() % 6);
    for (int k = 0; k < n; ++k) text += lines[rng() % lines.size()];
    text += square;
    text += "f 5 6 7 8\n";
    SCOPED_TRACE(text);
    check(text);
    if (::testing::Test::HasFailure()) break;  // one report is enough
  }
}
