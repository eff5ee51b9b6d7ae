// Tests for the Mesh model (qsp/polymesh.h) and its readers and writers (qsp/io.h): every corpus file
// reads, writes and reads back to the same model; an independent parser (tests/support/mesh_text.h)
// finds the same faces, corner positions, texture coordinates, normals, labels and tags in the input
// and in qsp's output; numbers keep their exact value; what a format cannot hold is refused by name.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "io_text.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"
#include "qsp/polymesh.h"
#include "support/corpus.h"
#include "support/files.h"
#include "support/mesh_compare.h"
#include "support/mesh_text.h"

namespace fs = std::filesystem;
using qsp::testing::canonical_decimal;
using qsp::testing::expect_same_mesh;
using qsp::testing::slurp;
using qsp::testing::TextMesh;

namespace {

template <class Fn>
std::string expect_error(Fn fn, qsp::ErrorCode code) {
  try {
    fn();
  } catch (const qsp::Error& e) {
    EXPECT_EQ(qsp::error_name(e.code()), std::string(qsp::error_name(code))) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "expected qsp::Error " << qsp::error_name(code);
  return "";
}

qsp::Mesh read_text(const std::string& text, qsp::MeshFormat format, qsp::ReadNotes* notes = nullptr) {
  switch (format) {
    case qsp::MeshFormat::kObj:
      return qsp::read_obj_mesh(text, "t.obj", notes);
    case qsp::MeshFormat::kOff:
      return qsp::read_off_mesh(text, "t.off", notes);
    default:
      return qsp::read_ply_mesh(text, "t.ply", notes);
  }
}

TextMesh parse_text(const std::string& text, qsp::MeshFormat format) {
  switch (format) {
    case qsp::MeshFormat::kObj:
      return qsp::testing::parse_obj_text(text);
    case qsp::MeshFormat::kOff:
      return qsp::testing::parse_off_text(text);
    default:
      return qsp::testing::parse_ply_bytes(text);
  }
}

// Whether the new reader must accept a corpus file: everything but faces repeating a vertex.
bool expected_mesh(const fs::path& p) {
  for (const fs::path& d : qsp::testing::shared_mesh_dirs()) {
    if (!fs::exists(d) || !fs::equivalent(d, p.parent_path())) continue;
    const auto rows = qsp::testing::read_manifest(d / "MANIFEST.tsv");
    const auto row = rows.find(p.filename().string());
    EXPECT_NE(row, rows.end()) << p;
    return row == rows.end() || row->second.num("degenerate_faces") == 0;
  }
  return true;
}

// The same content in two independent parses of OBJ text: faces corner for corner with the same
// positions, texture coordinates and normals at each corner, labels per face, tags, kept lines.
void expect_same_obj_content(const TextMesh& a, const TextMesh& b, bool same_arrays) {
  ASSERT_EQ(a.faces.size(), b.faces.size());
  for (std::size_t f = 0; f < a.faces.size(); ++f) {
    ASSERT_EQ(a.faces[f].size(), b.faces[f].size()) << "face " << f;
    for (std::size_t c = 0; c < a.faces[f].size(); ++c) {
      ASSERT_EQ(a.vertices.at(a.faces[f][c]), b.vertices.at(b.faces[f][c]))
          << "face " << f << " corner " << c;
      const long ta = a.face_texcoords[f][c], tb = b.face_texcoords[f][c];
      ASSERT_EQ(ta < 0, tb < 0) << "face " << f;
      if (ta >= 0) {
        ASSERT_EQ(a.texcoords.at(ta), b.texcoords.at(tb)) << "face " << f;
      }
      const long na = a.face_normals[f][c], nb = b.face_normals[f][c];
      ASSERT_EQ(na < 0, nb < 0) << "face " << f;
      if (na >= 0) {
        ASSERT_EQ(a.normals.at(na), b.normals.at(nb)) << "face " << f;
      }
    }
  }
  EXPECT_EQ(a.object, b.object);
  EXPECT_EQ(a.group, b.group);
  EXPECT_EQ(a.material, b.material);
  EXPECT_EQ(a.smoothing, b.smoothing);
  EXPECT_EQ(a.tags, b.tags);
  EXPECT_EQ(a.other_lines, b.other_lines);
  if (same_arrays) {
    EXPECT_EQ(a.vertices, b.vertices);
    EXPECT_EQ(a.texcoords, b.texcoords);
    EXPECT_EQ(a.normals, b.normals);
    EXPECT_EQ(a.faces, b.faces);
  }
}

void expect_same_content(const TextMesh& a, const TextMesh& b, qsp::MeshFormat format) {
  if (format == qsp::MeshFormat::kObj) return expect_same_obj_content(a, b, true);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.face_extra, b.face_extra);
  EXPECT_EQ(a.ply, b.ply);
}

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

// The float64 of every decimal.
std::vector<double> doubles(const std::vector<qsp::testing::Values>& rows) {
  std::vector<double> out;
  for (const auto& row : rows) {
    for (const std::string& d : row) {
      double x = 0;
      std::from_chars(d.data(), d.data() + d.size(), x);
      out.push_back(x);
    }
  }
  return out;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// The corpus

// Every mesh of testdata/ and ../shared (osd_shapes/ too): read, written in its own format, read back
// to an identical model; the independent parser finds the same content in the input and the output,
// and in the canonical-order OBJ. Files with a face repeating a vertex are refused, at their line.
TEST(MeshCorpus, EveryFileRoundTripsToTheSameModelAndContent) {
  int read = 0, refused = 0, expected = 0;
  for (const fs::path& p : qsp::testing::corpus()) {
    SCOPED_TRACE(p.string());
    const bool must_read = expected_mesh(p);
    expected += must_read;
    qsp::ReadNotes notes;
    qsp::Mesh m;
    try {
      m = qsp::read_mesh(p.string(), &notes);
    } catch (const qsp::Error& e) {
      EXPECT_FALSE(must_read) << e.what();
      EXPECT_EQ(e.code(), qsp::ErrorCode::kDegenerateFace) << e.what();
      EXPECT_NE(std::string(e.what()).find(p.string() + ":"), std::string::npos) << e.what();
      ++refused;
      continue;
    }
    EXPECT_TRUE(must_read);
    ++read;
    ASSERT_NO_THROW(qsp::check_mesh(m));
    EXPECT_EQ(notes.face_line.size(), m.face_count());
    const qsp::MeshFormat format = qsp::format_from_path(p.string());
    const std::string input = slurp(p);
    const std::string output = qsp::write_mesh(m, format);
    expect_same_mesh(m, read_text(output, format));
    expect_same_content(parse_text(input, format), parse_text(output, format), format);
    if (format == qsp::MeshFormat::kObj) {
      // The canonical order: the same faces, corners, values and labels, statements regrouped.
      const std::string canonical = qsp::write_obj_mesh(m, {.keep_order = false});
      expect_same_obj_content(parse_text(input, format), qsp::testing::parse_obj_text(canonical), false);
    }
    if (HasFailure()) break;  // one file's report is enough
  }
  EXPECT_EQ(read, expected);
  EXPECT_GE(read + refused, 20);
}

// The positions and faces of every corpus mesh written as binary PLY (both byte orders) and OFF, read
// back: the same numbers bit for bit, the same faces.
TEST(MeshCorpus, PositionsAndFacesSurviveEveryFormat) {
  int files = 0;
  for (const fs::path& p : qsp::testing::corpus()) {
    if (!expected_mesh(p)) continue;
    SCOPED_TRACE(p.string());
    qsp::Mesh m = qsp::read_mesh(p.string());
    qsp::drop(m, qsp::kCategoryAll);
    for (const auto ply :
         {qsp::PlyFormat::kBinaryLittleEndian, qsp::PlyFormat::kBinaryBigEndian, qsp::PlyFormat::kAscii}) {
      const qsp::Mesh back = qsp::read_ply_mesh(qsp::write_ply_mesh(m, {.ply_format = ply}), "t.ply");
      EXPECT_EQ(qsp::testing::numbers_difference(m.positions, back.positions), "");
      EXPECT_EQ(m.corner_vertices, back.corner_vertices);
      EXPECT_EQ(m.face_offsets, back.face_offsets);
    }
    const qsp::Mesh off = qsp::read_off_mesh(qsp::write_off_mesh(m), "t.off");
    EXPECT_EQ(qsp::testing::numbers_difference(m.positions, off.positions), "");
    EXPECT_EQ(m.corner_vertices, off.corner_vertices);
    ++files;
  }
  EXPECT_GE(files, 10);
}

namespace {

// One to three random byte edits of `text`: a byte replaced or inserted from `alphabet`, a digit changed,
// a byte erased.
void mutate(std::string& text, const std::string& alphabet, std::mt19937& rng) {
  for (int e = 1 + static_cast<int>(rng() % 3); e > 0 && !text.empty(); --e) {
    const std::size_t at = rng() % text.size();
    switch (rng() % 4) {
      case 0:
        text[at] = alphabet[rng() % alphabet.size()];
        break;
      case 3:  // another digit: often still valid
        if (text[at] >= '0' && text[at] <= '9') text[at] = static_cast<char>('0' + rng() % 10);
        break;
      case 1:
        text.insert(at, 1, alphabet[rng() % alphabet.size()]);
        break;
      default:
        text.erase(at, 1);
    }
  }
}

// The kinds (--drop categories) a Mesh carries, comments aside: what a QuadMesh reading reports.
unsigned mesh_categories(const qsp::Mesh& m) {
  unsigned out = 0;
  for (const qsp::CategoryName& c : qsp::kCategoryNames) {
    if (c.category != qsp::kCategoryComment && qsp::extras(m, c.category).any()) out |= c.category;
  }
  return out;
}

bool all_quads(const qsp::Mesh& m) {
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    if (m.degree(f) != 4) return false;
  }
  return true;
}

// Both readings of one text: where the exact one reads quads only, the QuadMesh one reads the same
// quads and reports the same kinds of data (so --drop means the same in both); where it reads other
// faces, the QuadMesh one refuses them; where only the QuadMesh one reads the text, the exact one refused
// for a check the QuadMesh readers do not make (README: texture coordinate, normal and tag indices in
// range, vertices agreeing on having colours). Returns whether both read it.
bool expect_readers_agree(const std::string& text, qsp::MeshFormat format) {
  qsp::Mesh m;
  std::string exact_error;
  qsp::ErrorCode exact_code{};
  try {
    m = read_text(text, format);
  } catch (const qsp::Error& e) {
    exact_error = e.what();
    exact_code = e.code();
  }
  qsp::ReadReport report;
  qsp::QuadMesh q;
  try {
    q = format == qsp::MeshFormat::kObj   ? qsp::read_obj(text, "t.obj", &report)
        : format == qsp::MeshFormat::kOff ? qsp::read_off(text, "t.off", &report)
                                          : qsp::read_ply(text, "t.ply", &report);
  } catch (const qsp::Error& e) {
    if (exact_error.empty()) {
      EXPECT_FALSE(all_quads(m)) << "only the exact reader reads it: " << e.what();
      EXPECT_EQ(e.code(), qsp::ErrorCode::kNotQuad) << e.what();
    }
    return false;
  }
  if (!exact_error.empty()) {
    const bool index =
        exact_code == qsp::ErrorCode::kBadIndex &&
        (exact_error.find("texture coordinate") != std::string::npos ||
         exact_error.find("normal") != std::string::npos || exact_error.find("`t ") != std::string::npos);
    const bool colours = exact_code == qsp::ErrorCode::kUnsupported &&
                         exact_error.find("first vertex (line") != std::string::npos;
    EXPECT_TRUE(index || colours) << "only the QuadMesh reader reads it; the exact one says " << exact_error;
    return false;
  }
  EXPECT_EQ(q.quads, m.corner_vertices);
  EXPECT_EQ(report.categories() & ~qsp::kCategoryComment, mesh_categories(m))
      << report.describe_extra_data("t");
  // The leading comment block the QuadMesh reading reports is where the exact reading's comments start.
  if (report.leading_comments.size() > m.comments.size()) {
    ADD_FAILURE() << "more leading comments than comments";
    return true;
  }
  EXPECT_TRUE(std::equal(report.leading_comments.begin(), report.leading_comments.end(), m.comments.begin()));
  EXPECT_EQ(report.kept_lines, m.verbatim.size());
  return true;
}

}  // namespace

// Every corpus file both readers read: the same quads, the same kinds of data.
TEST(MeshCorpus, BothReadingsReportTheSameKinds) {
  int both = 0;
  for (const fs::path& p : qsp::testing::corpus()) {
    if (!expected_mesh(p)) continue;
    SCOPED_TRACE(p.string());
    const qsp::MeshFormat format = qsp::format_from_path(p.string());
    both += expect_readers_agree(slurp(p), format);
    if (HasFailure()) break;
  }
  EXPECT_GE(both, qsp::testing::shared_present() ? 40 : 9);
}

// Mutants of a quad OBJ carrying every kind, with lines inserted that qsp keeps as text or refuses:
// the two readers agree as expect_readers_agree says.
TEST(MeshHostile, BothReadersAgreeOnMutants) {
  const std::string base =
      "# c\nmtllib m\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nvt 0 0\nvn 0 0 1\ng a b\n"
      "usemtl x\ns 1\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf 2 5 6 3\nt crease 2/1/0 0 1 2.5\n";
  const std::vector<std::string> lines = {
      "This is prose\n", "cstype bspline\n", "curv 0 1 1 2\n", "vp 1\n",      "t crease 3/1/0 0 1 2 1\n",
      "usemap x\n",      "l 1 2\n",          "deg 3\n",        "v 3 3 3 1\n", "o thing\n",
      "f 1 2 3\n",       "vt 1 1\n"};
  const std::string alphabet = "vftgsuo #/\\-+.0123456789e\n\r\n\nxnp";
  std::mt19937 rng(19);
  int both = 0;
  for (int round = 0; round < 1500; ++round) {
    std::string text = base;
    if (rng() % 4 != 0) {  // a whole line, at a line start
      const std::size_t start = text.rfind('\n', rng() % text.size());
      text.insert(start == std::string::npos ? 0 : start + 1, lines[rng() % lines.size()]);
    }
    if (rng() % 2) mutate(text, alphabet, rng);
    SCOPED_TRACE(text);
    both += expect_readers_agree(text, qsp::MeshFormat::kObj);
    if (HasFailure()) return;
  }
  EXPECT_GT(both, 300);  // enough read by both that the kinds are compared
}

// ---------------------------------------------------------------------------------------------
// Exact numbers

TEST(MeshNumbers, PrecisionIsTheNarrowestThatHoldsTheText) {
  struct Case {
    const char* text;
    qsp::Precision want;
  };
  const Case cases[] = {
      {"0.1", qsp::Precision::kFloat32},
      {"-0.3492", qsp::Precision::kFloat32},
      {"0.960000", qsp::Precision::kFloat32},
      {"16777216", qsp::Precision::kFloat32},
      {"0.12345679", qsp::Precision::kFloat32},  // float32's own shortest text
      {"3.4028235e38", qsp::Precision::kFloat32},
      {"1e-45", qsp::Precision::kFloat32},
      {"16777217", qsp::Precision::kFloat64},
      {"987654000", qsp::Precision::kFloat64},  // float32's shortest text is "987654016"
      {"123456000", qsp::Precision::kFloat32},  // an integer float32 holds
      {"0.6432291269", qsp::Precision::kFloat64},
      {"0.123456789", qsp::Precision::kFloat64},  // 9 digits float32 does not hold
      {"1e39", qsp::Precision::kFloat64},
      {"1e-50", qsp::Precision::kFloat64},
      {"0.30000000000000004", qsp::Precision::kFloat64},
      {"577766900000000128", qsp::Precision::kFloat64},     // a float64's shortest text: its exact integer
      {"123456789012345678", qsp::Precision::kDecimal},     // 18 digits: the nearest float64 is ...680
      {"0.3000000000000000444", qsp::Precision::kDecimal},  // 19 digits: no float64 print
      {"123456789012345678901234567890", qsp::Precision::kDecimal},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const std::string text = std::string("v ") + c.text + " 0 0\n";
    const qsp::Mesh m = qsp::read_obj_mesh(text, "t.obj");
    EXPECT_EQ(int(m.positions.precision), int(c.want));
    // Written back, the text denotes the same decimal.
    const std::string out = qsp::write_obj_mesh(m);
    const auto w = qsp::testing::split_words(out);
    ASSERT_GE(w.size(), 2u);
    EXPECT_EQ(canonical_decimal(w[1]), canonical_decimal(c.text)) << out;
    // The float32 mirror is std::from_chars's (or the rounded float64 beyond float32's range).
    float want = 0;
    const auto r = std::from_chars(c.text, c.text + std::strlen(c.text), want);
    if (r.ec == std::errc()) {
      EXPECT_EQ(bits(m.positions.f32[0]), bits(want));
    }
  }
  // Beyond float64's range: refused, as NaN and infinity are.
  expect_error([] { qsp::read_obj_mesh("v 1e400 0 0\n", "t.obj"); }, qsp::ErrorCode::kBadNumber);
  expect_error([] { qsp::read_obj_mesh("v 1e-400 0 0\n", "t.obj"); }, qsp::ErrorCode::kBadNumber);
  expect_error([] { qsp::read_obj_mesh("v nan 0 0\n", "t.obj"); }, qsp::ErrorCode::kBadNumber);
  // The QuadMesh reader still refuses what float32 cannot hold.
  expect_error([] { qsp::read_obj("v 1e39 0 0\n", "t.obj"); }, qsp::ErrorCode::kBadNumber);
}

// 7 to 9 digits: float32 holds the text exactly when the float's shortest text is the same decimal.
// The reader decides most of these without printing the float; its answer must be the printed one.
TEST(MeshNumbers, SevenToNineDigitsAgreeWithTheShortestText) {
  std::mt19937 rng(97);
  int float32 = 0, float64 = 0;
  for (int i = 0; i < 20000; ++i) {
    float f = 0;
    do {
      f = std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
    } while (!std::isnormal(f) || std::fabs(f) > 1e30f || std::fabs(f) < 1e-30f);
    char text[64];
    switch (i % 3) {
      case 0:  // the shortest text itself
        *std::to_chars(text, text + 63, f).ptr = '\0';
        break;
      case 1:  // printf's 8 or 9 significant digits
        std::snprintf(text, sizeof text, "%.*e", 7 + i % 2, static_cast<double>(f));
        break;
      default:  // a neighbour of the shortest text in its last digit
        std::snprintf(text, sizeof text, "%.*e", 6 + i % 3, static_cast<double>(f) * (1 + 1e-7 * (i % 5)));
    }
    float nearest = 0;
    std::from_chars(text, text + std::strlen(text), nearest);
    char shortest[64];
    *std::to_chars(shortest, shortest + 63, nearest).ptr = '\0';
    const bool holds = canonical_decimal(shortest) == canonical_decimal(text);
    const qsp::Mesh m = qsp::read_obj_mesh(std::string("v ") + text + " 0 0\n", "t.obj");
    ASSERT_EQ(m.positions.precision == qsp::Precision::kFloat32, holds)
        << text << " (shortest " << shortest << ")";
    // The fast paths round as std::from_chars does, in both readers.
    ASSERT_EQ(bits(m.positions.f32[0]), bits(nearest)) << text;
    ASSERT_EQ(bits(qsp::read_obj(std::string("v ") + text + " 0 0\n", "t.obj").positions[0]), bits(nearest))
        << text;
    (holds ? float32 : float64)++;
  }
  EXPECT_GT(float32, 5000);
  EXPECT_GT(float64, 5000);
}

// The writers keep the shortest text of floats already written (io_write.cpp, FloatTexts): with far
// more distinct floats than it holds, repeats near and far, and signed zeros, every number written is
// still its own shortest text, in OBJ and OFF.
TEST(MeshNumbers, RepeatedAndEvictedFloatsAreWrittenAsTheirShortestText) {
  std::mt19937 rng(7);
  std::vector<float> pool;
  for (int i = 0; i < 40000; ++i) {
    float f = 0;
    do {
      f = std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
    } while (!std::isfinite(f));
    pool.push_back(i % 7 == 0 ? std::ldexp(static_cast<float>(i), -12) : f);
  }
  pool.push_back(-0.0f);
  pool.push_back(0.0f);
  const auto shortest = [](float f) {
    char t[64];
    return std::string(t, std::to_chars(t, t + sizeof t, f).ptr);
  };
  std::string obj, off_rows;
  const int vertices = 30000;
  for (int v = 0; v < vertices; ++v) {
    std::string row;
    for (int k = 0; k < 3; ++k) {  // new floats, and ones written 1 to 30,000 numbers before
      const float f = pool[rng() % 3 == 0 ? pool.size() - 1 - rng() % 2 : rng() % pool.size()];
      if (k) row += ' ';
      row += shortest(f);
    }
    ((obj += "v ") += row) += '\n';
    (off_rows += row) += '\n';
  }
  for (int t = 0; t < 5000; ++t)
    obj += "vt " + shortest(pool[rng() % 64]) + " " + shortest(pool[rng() % 4096]) + "\n";
  obj += "f 1/1 2/2 3/3 4/4\n";
  const qsp::Mesh m = qsp::read_obj_mesh(obj, "t.obj");
  ASSERT_EQ(m.positions.precision, qsp::Precision::kFloat32);
  EXPECT_EQ(qsp::write_obj_mesh(m), obj);
  qsp::Mesh positions_only = m;
  positions_only.texcoords = qsp::Numbers{};
  positions_only.corner_texcoords.clear();
  positions_only.statements.clear();
  const std::string off = qsp::write_mesh(positions_only, qsp::MeshFormat::kOff);
  EXPECT_NE(off.find(off_rows), std::string::npos);
}

// Coordinates with 10 and 17 significant digits come back with the same doubles, through every
// format that holds them, and the independent parser reads the same decimals.
TEST(MeshNumbers, TenAndSeventeenDigitCoordinatesKeepTheirDoubles) {
  std::mt19937_64 rng(19);
  for (const int digits : {10, 17}) {
    SCOPED_TRACE(digits);
    std::string text;
    std::vector<double> want;
    std::vector<float> want32;
    for (int v = 0; v < 300; ++v) {
      text += "v";
      for (int k = 0; k < 3; ++k) {
        const double x = std::ldexp(static_cast<double>(rng() >> 11), -53) * 200.0 - 100.0;
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.*e", digits - 1, x);
        double d = 0;
        std::from_chars(buf, buf + std::strlen(buf), d);
        want.push_back(d);
        float f = 0;
        std::from_chars(buf, buf + std::strlen(buf), f);
        want32.push_back(f);
        text += std::string(" ") + buf;
      }
      text += "\n";
    }
    for (int f = 0; f + 3 < 300; f += 4)
      text += "f " + std::to_string(f + 1) + " " + std::to_string(f + 2) + " " + std::to_string(f + 3) + " " +
              std::to_string(f + 4) + "\n";
    const qsp::Mesh m = qsp::read_obj_mesh(text, "t.obj");
    ASSERT_NE(m.positions.precision, qsp::Precision::kFloat32);
    EXPECT_TRUE(qsp::testing::same_bits(m.positions.f64, want));
    // The float32 mirror is std::from_chars's float of each text, and the QuadMesh reader's.
    EXPECT_TRUE(qsp::testing::same_bits(m.positions.f32, want32));
    EXPECT_TRUE(qsp::testing::same_bits(qsp::read_obj(text, "t.obj").positions, want32));
    for (const qsp::MeshFormat format :
         {qsp::MeshFormat::kObj, qsp::MeshFormat::kOff, qsp::MeshFormat::kPly}) {
      const std::string out = qsp::write_mesh(m, format);
      EXPECT_TRUE(qsp::testing::same_bits(read_text(out, format).positions.f64, want));
      // Independently: the same doubles (17 digits are spelling beyond the double's shortest text).
      EXPECT_EQ(doubles(parse_text(out, format).vertices),
                doubles(qsp::testing::parse_obj_text(text).vertices));
      if (digits == 10) {
        EXPECT_EQ(parse_text(out, format).vertices, qsp::testing::parse_obj_text(text).vertices);
      }
    }
    qsp::Mesh binary = m;
    binary.ply = {};
    const qsp::Mesh back = qsp::read_ply_mesh(
        qsp::write_ply_mesh(binary, {.ply_format = qsp::PlyFormat::kBinaryLittleEndian}), "b.ply");
    EXPECT_TRUE(qsp::testing::same_bits(back.positions.f64, want));
  }
}

// pmp_hole_capsule.off has ten significant digits: kept, not rounded to float32.
TEST(MeshNumbers, HoleCapsuleKeepsItsTenDigits) {
  QSP_NEEDS_SHARED();
  const fs::path p = qsp::testing::shared_dir() / "meshes" / "pmp_hole_capsule.off";
  const qsp::Mesh m = qsp::read_mesh(p.string());
  EXPECT_EQ(m.positions.precision, qsp::Precision::kFloat64);
  const std::string out = qsp::write_off_mesh(m);
  EXPECT_NE(out.find("0.6432291269"), std::string::npos);
  EXPECT_EQ(qsp::testing::parse_off_text(out).vertices, qsp::testing::parse_off_text(slurp(p)).vertices);
}

// More than 17 digits: the decimal digits themselves, written back exactly.
TEST(MeshNumbers, DecimalsBeyondFloat64AreKeptAsDigits) {
  const std::string text =
      "v 0.12345678901234567890123 -98765432109876543210 1e-30\nvt 0.5 "
      "0.000000000000000000000000012345678901234567890\n";
  const qsp::Mesh m = qsp::read_obj_mesh(text, "t.obj");
  EXPECT_EQ(m.positions.precision, qsp::Precision::kDecimal);
  ASSERT_EQ(m.positions.decimals.size(), 2u);
  EXPECT_EQ(m.positions.decimals[0].digits, "12345678901234567890123");
  EXPECT_EQ(m.positions.decimals[1].digits, "9876543210987654321");
  EXPECT_TRUE(m.positions.decimals[1].negative);
  EXPECT_EQ(m.texcoords.precision, qsp::Precision::kDecimal);
  const std::string out = qsp::write_obj_mesh(m);
  EXPECT_EQ(qsp::testing::parse_obj_text(out).vertices, qsp::testing::parse_obj_text(text).vertices);
  EXPECT_EQ(qsp::testing::parse_obj_text(out).texcoords, qsp::testing::parse_obj_text(text).texcoords);
  expect_same_mesh(m, qsp::read_obj_mesh(out, "back.obj"));
  // Binary PLY cannot hold them; ASCII PLY can.
  qsp::Mesh ply = m;
  qsp::drop(ply, qsp::kCategoryUv);
  const std::string msg =
      expect_error([&] { qsp::write_ply_mesh(ply, {.ply_format = qsp::PlyFormat::kBinaryLittleEndian}); },
                   qsp::ErrorCode::kUnsupported);
  EXPECT_NE(msg.find("ASCII"), std::string::npos) << msg;
  EXPECT_EQ(qsp::testing::numbers_difference(qsp::read_ply_mesh(qsp::write_ply_mesh(ply), "t.ply").positions,
                                             ply.positions),
            "");
}

// The precision is the narrowest class holding the values, not the spelling: a 16- or 17-digit print
// is its float64, and when that float64's shortest text is a float32's ("0.10000000000000001" is 0.1)
// float32 holds the value. fuzz_read_mesh: such a coordinate made a whole ASCII PLY column float64,
// written back as "-1.43542", which read back as float32 (read(write(m)) != m).
TEST(MeshNumbers, PrecisionComesFromTheValueNotItsSpelling) {
  struct Case {
    const char* text;
    qsp::Precision want;
    const char* value;  // the shortest text written back
  };
  const Case cases[] = {
      {"0.10000000000000001", qsp::Precision::kFloat32, "0.1"},
      {"-1.43541999999999990", qsp::Precision::kFloat32, "-1.43542"},  // the finding's coordinate
      {"-0.47999999999999998", qsp::Precision::kFloat32, "-0.48"},
      {"1.0000000000000000", qsp::Precision::kFloat32, "1"},
      {"16777216.000000001", qsp::Precision::kFloat32, "16777216"},
      {"987654016.00000001", qsp::Precision::kFloat32, "987654016"},  // float32's integer shortest text
      {"0.30000000000000004", qsp::Precision::kFloat64, "0.30000000000000004"},
      {"0.1000000000000001", qsp::Precision::kFloat64, "0.1000000000000001"},
      {"9.8765432100000001", qsp::Precision::kFloat64, "9.87654321"},  // not float32's shortest text
      {"-1.2345678901234567e+20", qsp::Precision::kFloat64, "-123456789012345667584"},  // its exact integer
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    for (const qsp::MeshFormat format :
         {qsp::MeshFormat::kObj, qsp::MeshFormat::kOff, qsp::MeshFormat::kPly}) {
      SCOPED_TRACE(int(format));
      const std::string xyz = std::string(c.text) + " 0.5 -0.48";
      const std::string text = format == qsp::MeshFormat::kObj ? "v " + xyz + "\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
                               : format == qsp::MeshFormat::kOff
                                   ? "OFF\n3 1 0\n" + xyz + "\n1 0 0\n0 1 0\n3 0 1 2\n"
                                   : "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                     "property float y\nproperty float z\nelement face 1\n"
                                     "property list uchar int vertex_indices\nend_header\n" +
                                         xyz + "\n1 0 0\n0 1 0\n3 0 1 2\n";
      const qsp::Mesh m = read_text(text, format);
      EXPECT_EQ(int(m.positions.precision), int(c.want));
      const std::string out = qsp::write_mesh(m, format);
      EXPECT_NE(out.find(std::string(c.value) + " 0.5 -0.48"), std::string::npos) << out;
      const qsp::Mesh back = read_text(out, format);
      expect_same_mesh(m, back);
      EXPECT_EQ(qsp::write_mesh(back, format), out);
    }
  }
}

// The same property over random values: 16- and 17-digit prints of float32 values, of float64
// values, and of neighbours within a float64's rounding; each read in every text format is the class
// its value needs (decided independently, from the value's shortest text), and comes back unchanged.
TEST(MeshNumbers, SixteenAndSeventeenDigitPrintsRoundTripInEveryFormat) {
  std::mt19937_64 rng(41);
  int float32 = 0, float64 = 0;
  for (int i = 0; i < 6000; ++i) {
    double d = 0;
    if (i % 2 == 0) {
      float f = 0;
      do {
        f = std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
      } while (!std::isfinite(f) || std::fabs(f) > 1e30f || std::fabs(f) < 1e-30f);
      char shortest[64];  // the float64 of the float's shortest text
      const auto r = std::to_chars(shortest, shortest + sizeof shortest, f);
      std::from_chars(shortest, r.ptr, d);
    } else {
      d = std::ldexp(static_cast<double>(rng() >> 11), -53) *
          std::ldexp(1.0, static_cast<int>(rng() % 60) - 30);
    }
    char text[64];
    std::snprintf(text, sizeof text, "%.*e", 15 + i % 2, d);
    if (i % 3 == 2) {  // a neighbour in the last digit: the same float64, or the next one
      char* e = std::strchr(text, 'e');
      if (e[-1] < '9') ++e[-1];
    }
    const std::string value = qsp::testing::number_value(text);
    float nearest = 0;
    std::from_chars(value.data(), value.data() + value.size(), nearest);  // the float32 of the value
    const bool holds = qsp::testing::decimal_of(nearest) == value;
    (holds ? float32 : float64)++;
    const std::string obj = std::string("v ") + text + " 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const qsp::Mesh m = qsp::read_obj_mesh(obj, "t.obj");
    ASSERT_EQ(m.positions.precision == qsp::Precision::kFloat32, holds) << text << " is " << value;
    ASSERT_EQ(bits(m.positions.f32[0]), bits(nearest)) << text;
    for (const qsp::MeshFormat format :
         {qsp::MeshFormat::kObj, qsp::MeshFormat::kOff, qsp::MeshFormat::kPly}) {
      const qsp::Mesh back = read_text(qsp::write_mesh(m, format), format);
      ASSERT_EQ(qsp::testing::numbers_difference(m.positions, back.positions), "") << text;
    }
  }
  EXPECT_GT(float32, 2000);
  EXPECT_GT(float64, 2000);
}

// A 16- or 17-digit print of a float64 lying exactly halfway between two float32s: the print may
// round to one float32 and the float64's shortest text to the other. The float32 mirror is the
// shortest text's, so writing it (as the shortest text) does not change it.
TEST(MeshNumbers, AFloat64HalfwayBetweenFloat32sKeepsItsMirror) {
  struct Case {
    const char* text;
    const char* shortest;  // of its float64, exactly halfway
  };
  const Case cases[] = {
      {"0.50000002980232238", "0.5000000298023224"},  // 0.5 + 2^-25, between 0.5 and 0.50000006
      {"16777217.000000001", "16777217"},             // 2^24 + 1, between 16777216 and 16777218
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const qsp::Mesh m =
        qsp::read_obj_mesh(std::string("v ") + c.text + " 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "t.obj");
    EXPECT_EQ(m.positions.precision, qsp::Precision::kFloat64);
    float want = 0;
    std::from_chars(c.shortest, c.shortest + std::strlen(c.shortest), want);
    EXPECT_EQ(bits(m.positions.f32[0]), bits(want));
    for (const qsp::MeshFormat format :
         {qsp::MeshFormat::kObj, qsp::MeshFormat::kOff, qsp::MeshFormat::kPly}) {
      const std::string out = qsp::write_mesh(m, format);
      EXPECT_NE(out.find(c.shortest), std::string::npos) << out;
      EXPECT_EQ(qsp::testing::numbers_difference(read_text(out, format).positions, m.positions), "");
    }
  }
}

// ---------------------------------------------------------------------------------------------
// OBJ content

TEST(MeshObj, EverythingAFileCarriesIsKeptInItsOrder) {
  const std::string text =
      "# licence line 1\n"
      "#licence line 2\n"
      "mtllib a.mtl b.mtl\n"
      "o thing\n"
      "v 0 0 0 1 0 0\n"
      "v 1 0 0 0 1 0\n"
      "v 1 1 0 0 0 1\n"
      "v 0 1 0 1 1 1\n"
      "v 2 0 0 0.5 0.5 0.5\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
      "vn 0 0 1\n"
      "vp 0.5 0.5\n"
      "g left side\n"
      "usemtl red\n"
      "s 1\n"
      "f 1/1/1 2/2/1 3/3/1 4/4/1\n"
      "f 2/2 5/1 3/3\n"  // a triangle, texture coordinates only
      "usemtl blue\n"
      "f -4//1 -3//1 -2//1\n"
      "g right\n"
      "s off\n"
      "f 1 2 3 4 5\n"
      "# body comment\n"
      "t crease 2/1/0 0 1 4.0\n"
      "t interpolateboundary 1/0/0 2\n";
  qsp::ReadNotes notes;
  const qsp::Mesh m = qsp::read_obj_mesh(text, "t.obj", &notes);
  ASSERT_EQ(m.face_count(), 4u);
  EXPECT_EQ(m.face_offsets, (std::vector<std::uint32_t>{0, 4, 7, 10, 15}));
  EXPECT_EQ(m.corner_vertices, (std::vector<std::uint32_t>{0, 1, 2, 3, 1, 4, 2, 1, 2, 3, 0, 1, 2, 3, 4}));
  const std::uint32_t x = qsp::kInvalid;
  EXPECT_EQ(m.corner_texcoords, (std::vector<std::uint32_t>{0, 1, 2, 3, 1, 0, 2, x, x, x, x, x, x, x, x}));
  EXPECT_EQ(m.corner_normals, (std::vector<std::uint32_t>{0, 0, 0, 0, x, x, x, 0, 0, 0, x, x, x, x, x}));
  EXPECT_EQ(m.vertex_color_components, 3);
  EXPECT_EQ(m.vertex_colors.size(), 15u);
  EXPECT_EQ(m.objects.names, (std::vector<std::string>{"thing"}));
  EXPECT_EQ(m.objects.face, (std::vector<std::uint32_t>{0, 0, 0, 0}));
  EXPECT_EQ(m.groups.names, (std::vector<std::string>{"left side", "right"}));
  EXPECT_EQ(m.groups.face, (std::vector<std::uint32_t>{0, 0, 0, 1}));
  EXPECT_EQ(m.materials.face, (std::vector<std::uint32_t>{0, 0, 1, 1}));
  EXPECT_EQ(m.smoothing.names, (std::vector<std::string>{"1", "off"}));
  EXPECT_EQ(m.material_libraries, (std::vector<std::string>{"a.mtl b.mtl"}));
  EXPECT_EQ(m.comments, (std::vector<std::string>{" licence line 1", "licence line 2", " body comment"}));
  EXPECT_EQ(m.verbatim, (std::vector<std::string>{"vp 0.5 0.5"}));
  ASSERT_EQ(m.tags.size(), 2u);
  EXPECT_EQ(m.tags[0].ints, (std::vector<std::int64_t>{0, 1}));
  EXPECT_EQ(m.tags[0].floats.f32, (std::vector<float>{4.0f}));
  EXPECT_EQ(notes.warning_count, 1u);  // the `vp` line
  ASSERT_EQ(notes.warnings.size(), 1u);
  EXPECT_EQ(notes.warnings[0].line, 15u);
  EXPECT_EQ(notes.face_line, (std::vector<std::uint32_t>{19, 20, 22, 25}));
  // Written back: the same statements in the same order (numbers in their shortest spelling).
  const std::string out = qsp::write_obj_mesh(m);
  EXPECT_EQ(out,
            "# licence line 1\n#licence line 2\nmtllib a.mtl b.mtl\no thing\n"
            "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\nv 2 0 0 0.5 0.5 0.5\n"
            "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nvp 0.5 0.5\ng left side\nusemtl red\ns 1\n"
            "f 1/1/1 2/2/1 3/3/1 4/4/1\nf 2/2 5/1 3/3\nusemtl blue\nf 2//1 3//1 4//1\ng right\ns off\n"
            "f 1 2 3 4 5\n# body comment\nt crease 2/1/0 0 1 4\nt interpolateboundary 1/0/0 2\n");
  expect_same_mesh(m, qsp::read_obj_mesh(out, "back.obj"));
  // The canonical order: comments, libraries and kept lines first, labels where they change.
  EXPECT_EQ(qsp::write_obj_mesh(m, {.keep_order = false}),
            "# licence line 1\n#licence line 2\n# body comment\nmtllib a.mtl b.mtl\nvp 0.5 0.5\n"
            "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\nv 2 0 0 0.5 0.5 0.5\n"
            "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\no thing\ng left side\nusemtl red\ns 1\n"
            "f 1/1/1 2/2/1 3/3/1 4/4/1\nf 2/2 5/1 3/3\nusemtl blue\nf 2//1 3//1 4//1\ng right\ns off\n"
            "f 1 2 3 4 5\nt crease 2/1/0 0 1 4\nt interpolateboundary 1/0/0 2\n");
  // The QuadMesh reader still refuses the triangle and the pentagon.
  expect_error([&] { qsp::read_obj(text, "t.obj"); }, qsp::ErrorCode::kNotQuad);
}

// A MakeHuman asset with a stray line of prose between its licence and its vertices: read, with a
// warning naming the line; written back in place. The QuadMesh reader reads the same quads and counts
// the line as kept text (the `extra` kind compress refuses until told to drop it), at the same line.
TEST(MeshObj, StrayProseIsKeptWithAWarning) {
  const std::string fedora = slurp(fs::path(QSP_TESTDATA_DIR) / "mh_fedora.obj");
  const std::size_t first_v = fedora.find("\nv ") + 1;
  const std::string prose = "This asset was converted by hand, see the wiki for details\n";
  const std::string text = fedora.substr(0, first_v) + prose + fedora.substr(first_v);
  const long line = std::count(text.begin(), text.begin() + static_cast<long>(first_v), '\n') + 1;
  qsp::ReadNotes notes;
  const qsp::Mesh m = qsp::read_obj_mesh(text, "hat.obj", &notes);
  ASSERT_EQ(notes.warning_count, 1u);
  EXPECT_EQ(notes.warnings[0].line, static_cast<std::uint64_t>(line));
  EXPECT_NE(notes.warnings[0].message.find("unknown statement 'This'"), std::string::npos);
  EXPECT_NE(notes.describe_warnings("hat.obj").find("hat.obj:" + std::to_string(line) + ": kept as text"),
            std::string::npos);
  EXPECT_EQ(m.verbatim, (std::vector<std::string>{prose.substr(0, prose.size() - 1)}));
  const std::string out = qsp::write_obj_mesh(m);
  EXPECT_NE(out.find(prose + "v "), std::string::npos);
  const qsp::Mesh plain = qsp::read_obj_mesh(fedora, "hat.obj");
  EXPECT_EQ(m.corner_vertices, plain.corner_vertices);
  EXPECT_EQ(qsp::testing::numbers_difference(m.positions, plain.positions), "");
  // Read, written, read again: the kept line stays where it was, the rest is the same model.
  qsp::ReadNotes again;
  expect_same_mesh(m, qsp::read_obj_mesh(out, "hat2.obj", &again));
  EXPECT_EQ(again.warnings.at(0).line, notes.warnings[0].line);
  qsp::Mesh dropped = m;
  EXPECT_EQ(qsp::drop(dropped, qsp::kCategoryExtra).verbatim, 1u);
  expect_same_mesh(dropped, plain);
  EXPECT_EQ(qsp::write_obj_mesh(dropped), qsp::write_obj_mesh(plain));
  qsp::ReadReport report, plain_report;
  const qsp::QuadMesh q = qsp::read_obj(text, "hat.obj", &report);
  const qsp::QuadMesh plain_q = qsp::read_obj(fedora, "hat.obj", &plain_report);
  EXPECT_EQ(q.quads, plain_q.quads);
  EXPECT_TRUE(qsp::testing::same_bits(q.positions, plain_q.positions));
  EXPECT_EQ(report.kept_lines, 1u);
  EXPECT_EQ(report.first_kept.line, static_cast<std::uint64_t>(line));
  EXPECT_EQ(report.categories(), plain_report.categories() | qsp::kCategoryExtra);
  EXPECT_EQ(plain_report.categories() & qsp::kCategoryExtra, 0u);
  EXPECT_NE(report.describe_extra_data("hat.obj", qsp::kCategoryExtra)
                .find("the first at hat.obj:" + std::to_string(line) + ": unknown statement 'This'"),
            std::string::npos)
      << report.describe_extra_data("hat.obj");
}

// A kept line starting with a byte order mark, first in the file, keeps it (fuzz_read_mesh found it
// lost: a leading mark is not content).
TEST(MeshObj, KeptLineStartingWithAByteOrderMark) {
  const std::string text =
      " \xEF\xBB\xBF"
      "f1 \n";
  const qsp::Mesh m = qsp::read_obj_mesh(text, "t.obj");
  ASSERT_EQ(m.verbatim, (std::vector<std::string>{"\xEF\xBB\xBF"
                                                  "f1"}));
  expect_same_mesh(m, qsp::read_obj_mesh(qsp::write_obj_mesh(m), "back.obj"));
  expect_same_mesh(m, qsp::read_obj_mesh(qsp::write_obj_mesh(m, {.keep_order = false}), "back.obj"));
}

// Text ending in a continuation that joined an empty line keeps its backslash; written back, it must
// not join the next statement (fuzz_read_mesh found a vertex swallowed by a kept line and an object name).
TEST(MeshObj, TextEndingInABackslashDoesNotJoinTheNextLine) {
  for (const std::string text : {"e \\\n\nv 0 1 0\n", "v 0 0 0\nv 1 0 0\nv 1 1 0\no a\\\n\nf 1 2 3\n",
                                 "mtllib m\\\n\nv 0 0 0\n", "v 0 0 0\n1e39 3 \\\r\n\r\nv 1 1 1\n"}) {
    SCOPED_TRACE(text);
    const qsp::Mesh m = qsp::read_obj_mesh(text, "t.obj");
    expect_same_mesh(m, qsp::read_obj_mesh(qsp::write_obj_mesh(m), "back.obj"));
    const qsp::Mesh canonical = qsp::read_obj_mesh(qsp::write_obj_mesh(m, {.keep_order = false}), "back.obj");
    qsp::Mesh regrouped = m;  // the canonical order regroups the statements, and keeps all else
    regrouped.statements = canonical.statements;
    expect_same_mesh(regrouped, canonical);
  }
}

TEST(MeshObj, FreeFormAttributesAreKeptAndGeometryRefused) {
  qsp::ReadNotes notes;
  const std::string attrs = "v 0 0 0\nv 1 0 0\nv 1 1 0\ncstype bspline\ndeg 3\nf 1 2 3\nend\n";
  const qsp::Mesh m = qsp::read_obj_mesh(attrs, "t.obj", &notes);
  EXPECT_EQ(m.verbatim, (std::vector<std::string>{"cstype bspline", "deg 3", "end"}));
  EXPECT_EQ(notes.warning_count, 3u);
  EXPECT_EQ(qsp::write_obj_mesh(m), attrs);
  for (const char* geometry : {"curv 0 1 1 2\n", "surf 0 1 0 1 1 2 3\n", "curv2 1 2\n", "l 1 2\n", "p 1\n"}) {
    SCOPED_TRACE(geometry);
    expect_error([&] { qsp::read_obj_mesh(attrs + geometry, "t.obj"); }, qsp::ErrorCode::kUnsupported);
  }
}

TEST(MeshObj, NotAMeshIsRefusedWithItsLine) {
  const std::string square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
  struct Case {
    std::string text;
    qsp::ErrorCode code;
    const char* message;
  };
  const Case cases[] = {
      {square + "f 1 2 3 1\n", qsp::ErrorCode::kDegenerateFace,
       "t.obj:5: face repeats vertex 1 (corners 1 and 4)"},
      {square + "f 1 2 3 4 2\n", qsp::ErrorCode::kDegenerateFace, "t.obj:5: face repeats vertex 2"},
      {square + "f 1 2\n", qsp::ErrorCode::kDegenerateFace, "t.obj:5: face has 2 vertices"},
      {square + "f 0 1 2\n", qsp::ErrorCode::kBadIndex, "t.obj:5: vertex index 0"},
      {square + "f 1 2 9\n", qsp::ErrorCode::kBadIndex, "t.obj:5: vertex index 9 is out of range"},
      {square + "vt 0 0\nf 1/1 2/2 3/1\n", qsp::ErrorCode::kBadIndex, "t.obj:6: texture coordinate index 2"},
      {square + "f 1//-1 2//1 3//1\n", qsp::ErrorCode::kBadIndex, "t.obj:5: normal index in '1//-1'"},
      {square + "f 1 2 3\nt corner 1/1/0 7 2.0\n", qsp::ErrorCode::kBadIndex,
       "t.obj:6: `t corner` refers to vertex 7"},
      {square + "f 1 2 3\nt hole 1/0/0 1\n", qsp::ErrorCode::kBadIndex, "t.obj:6: `t hole` refers to face 1"},
      {square + "v 1 2 3 0.5 0.5 0.5\n", qsp::ErrorCode::kUnsupported,
       "t.obj:5: `v` has 6 numbers but the first vertex (line 1) has 3"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const std::string msg = expect_error([&] { qsp::read_obj_mesh(c.text, "t.obj"); }, c.code);
    EXPECT_NE(msg.find(c.message), std::string::npos) << msg;
  }
}

TEST(MeshObj, TagsIndexWhatOpenSubdivSays) {
  EXPECT_EQ(qsp::tag_indices("crease"), qsp::TagIndices::kEdges);
  EXPECT_EQ(qsp::tag_indices("corner"), qsp::TagIndices::kVertices);
  EXPECT_EQ(qsp::tag_indices("hole"), qsp::TagIndices::kFaces);
  EXPECT_EQ(qsp::tag_indices("interpolateboundary"), qsp::TagIndices::kNone);
  EXPECT_EQ(qsp::tag_indices("creasemethod"), qsp::TagIndices::kNone);
  EXPECT_EQ(qsp::tag_indices("vertexedit"), qsp::TagIndices::kUnknown);
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
      "t crease 4/2/0 0 1 1 2 2.5 10\n"
      "t creasemethod 0/0/1 chaikin\n"
      "t faceedit 4/0/1 3 4 1 1 hole\n"
      "t crease 3/1/0 0 1 2 1\n"  // an odd number of crease indices: kept as text
      "t corner 2/1/0 1\n";       // fewer arguments than declared: kept as text
  qsp::ReadNotes notes;
  const qsp::Mesh m = qsp::read_obj_mesh(text, "t.obj", &notes);
  ASSERT_EQ(m.tags.size(), 3u);
  EXPECT_EQ(m.tags[0].floats.f32, (std::vector<float>{2.5f, 10.0f}));
  EXPECT_EQ(m.tags[1].strings, (std::vector<std::string>{"chaikin"}));
  EXPECT_EQ(m.tags[2].name, "faceedit");
  EXPECT_EQ(m.verbatim.size(), 2u);
  EXPECT_EQ(notes.warning_count, 2u);
  EXPECT_EQ(qsp::write_obj_mesh(m), text);
}

TEST(MeshObj, ShorterTextureCoordinatesGetTheDefaultZero) {
  const qsp::Mesh m = qsp::read_obj_mesh("vt 0.5\nvt 0.25 0.75\nvt 1 1 1\nvt 0.125\n", "t.obj");
  EXPECT_EQ(m.texcoord_components, 3);
  EXPECT_EQ(m.texcoords.f32, (std::vector<float>{0.5f, 0, 0, 0.25f, 0.75f, 0, 1, 1, 1, 0.125f, 0, 0}));
}

// ---------------------------------------------------------------------------------------------
// OFF and PLY

TEST(MeshOff, VariantsColoursAndPolygons) {
  const std::string text =
      "# from a tool\nSTCNOFF\n4 2 0\n"
      "0 0 0 0 0 1 255 0 0 0 0\n1 0 0 0 0 1 0 255 0 1 0\n1 1 0 0 0 1 0 0 255 1 1\n0 1 0 0 0 1 9 9 9 0 1\n"
      "3 0 1 2 0.5 0.5 0.5\n3 0 2 3 1 1 1\n";
  const qsp::Mesh m = qsp::read_off_mesh(text, "t.off");
  EXPECT_EQ(m.face_offsets, (std::vector<std::uint32_t>{0, 3, 6}));
  EXPECT_EQ(m.vertex_color_components, 3);
  EXPECT_EQ(m.face_color_components, 3);
  EXPECT_EQ(m.corner_normals, m.corner_vertices);
  EXPECT_EQ(m.corner_texcoords, m.corner_vertices);
  EXPECT_EQ(m.comments, (std::vector<std::string>{" from a tool"}));
  const std::string out = qsp::write_off_mesh(m);
  EXPECT_EQ(out,  // the comment after the keyword line, which readers recognise OFF by
            "STCNOFF\n# from a tool\n4 2 0\n0 0 0 0 0 1 255 0 0 0 0\n1 0 0 0 0 1 0 255 0 1 0\n"
            "1 1 0 0 0 1 0 0 255 1 1\n0 1 0 0 0 1 9 9 9 0 1\n3 0 1 2 0.5 0.5 0.5\n3 0 2 3 1 1 1\n");
  expect_same_mesh(m, qsp::read_off_mesh(out, "back.off"));
  // Per-vertex attributes go to OBJ as corner indices, and to PLY as vertex properties.
  const qsp::Mesh ply = qsp::read_ply_mesh(qsp::write_ply_mesh(m), "t.ply");
  EXPECT_EQ(qsp::testing::numbers_difference(ply.normals, m.normals), "");
  EXPECT_EQ(qsp::testing::numbers_difference(ply.face_colors, m.face_colors), "");
  EXPECT_EQ(ply.corner_texcoords, m.corner_texcoords);
  expect_error([&] { qsp::read_off_mesh("COFF\n2 0 0\n0 0 0 1 1 1\n0 0 1 1 1 1 1\n", "t.off"); },
               qsp::ErrorCode::kUnsupported);
  expect_error([&] { qsp::read_off_mesh("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 1\n3 0 2 1\n", "t.off"); },
               qsp::ErrorCode::kUnsupported);
}

// What a format cannot hold is refused by name, with the category that drops it.
TEST(MeshFormats, WhatAFormatCannotHoldIsRefusedByName) {
  const std::string seams =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
      "g a\nusemtl m\nf 1/1 2/2 3/3 4/4\nf 1/5 3/3 4/4\nt corner 1/1/0 0 1\n";
  qsp::Mesh m = qsp::read_obj_mesh(seams, "t.obj");
  for (const auto& [write, format] : std::vector<std::pair<std::function<std::string()>, const char*>>{
           {[&] { return qsp::write_off_mesh(m); }, "OFF"},
           {[&] { return qsp::write_ply_mesh(m); }, "PLY"}}) {
    const std::string msg = expect_error(write, qsp::ErrorCode::kUnsupported);
    EXPECT_EQ(msg.rfind(std::string(format) + " cannot hold", 0), 0u) << msg;
    for (const char* drop : {"--drop uv", "--drop group", "--drop material", "--drop tag"})
      EXPECT_NE(msg.find(drop), std::string::npos) << msg;
  }
  const qsp::Extras dropped = qsp::drop(m, qsp::parse_categories("uv,group,material,tag"));
  EXPECT_EQ(dropped.describe(), "5 texture coordinates, 1 group, 1 material, 1 subdivision tag");
  EXPECT_FALSE(qsp::extras(m).any());
  EXPECT_EQ(qsp::write_off_mesh(m), "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n3 0 2 3\n");
  EXPECT_EQ(qsp::write_obj_mesh(m), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 3 4\n");
  // PLY properties and face colours have no place in OBJ.
  const qsp::Mesh ply = qsp::read_ply_mesh(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar quality\nelement face 1\nproperty list uchar int vertex_indices\nproperty uchar red\n"
      "property uchar green\nproperty uchar blue\nend_header\n0 0 0 1\n1 0 0 2\n0 1 0 3\n3 0 1 2 255 0 0\n",
      "t.ply");
  const std::string msg = expect_error([&] { qsp::write_obj_mesh(ply); }, qsp::ErrorCode::kUnsupported);
  EXPECT_NE(msg.find("1 face colours (--drop color)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("1 PLY properties (--drop extra)"), std::string::npos) << msg;
  expect_error([] { qsp::parse_categories("uv,colours"); }, qsp::ErrorCode::kUsage);
  EXPECT_EQ(qsp::parse_categories("all"), unsigned{qsp::kCategoryAll});
}

// A binary PLY with properties of every type, a list property and a face colour: read and written
// back byte for byte, in both byte orders and as ASCII.
TEST(MeshPly, BinaryFilesComeBackByteForByte) {
  const auto header = [](const char* format) {
    return std::string("ply\nformat ") + format +
           " 1.0\ncomment made by hand\nobj_info a test\nelement vertex 4\nproperty double z\nproperty float "
           "x\n"
           "property float y\nproperty short temperature\nproperty uchar red\nproperty uchar green\n"
           "property uchar blue\nproperty float nx\nproperty float ny\nproperty float nz\n"
           "element face 2\nproperty list uchar uint vertex_indices\nproperty list uchar float texcoord\n"
           "property int flags\nend_header\n";
  };
  std::mt19937 rng(3);
  for (const bool little : {true, false}) {
    std::string bytes = header(little ? "binary_little_endian" : "binary_big_endian");
    const auto put = [&](std::uint64_t v, int n) {
      for (int i = 0; i < n; ++i) bytes += static_cast<char>((v >> (8 * (little ? i : n - 1 - i))) & 0xFF);
    };
    for (int v = 0; v < 4; ++v) {
      put(std::bit_cast<std::uint64_t>(0.1 * v + 1e-17), 8);
      put(std::bit_cast<std::uint32_t>(static_cast<float>(rng()) / 7.0f), 4);
      put(std::bit_cast<std::uint32_t>(-0.0f), 4);
      put(static_cast<std::uint16_t>(-300 + v), 2);
      put(200, 1);
      put(v, 1);
      put(255 - v, 1);
      for (int k = 0; k < 3; ++k) put(std::bit_cast<std::uint32_t>(k == 2 ? 1.0f : 0.0f), 4);
    }
    for (int f = 0; f < 2; ++f) {
      put(3, 1);
      for (const std::uint32_t c : {0u, 1u + f, 2u + f}) put(c, 4);
      put(6, 1);
      for (int k = 0; k < 6; ++k) put(std::bit_cast<std::uint32_t>(0.25f * k), 4);
      put(static_cast<std::uint32_t>(-1 - f), 4);
    }
    const qsp::Mesh m = qsp::read_ply_mesh(bytes, "t.ply");
    EXPECT_EQ(m.positions.precision, qsp::Precision::kFloat64);
    EXPECT_EQ(m.vertex_color_components, 3);
    EXPECT_EQ(m.corner_normals, m.corner_vertices);
    ASSERT_EQ(m.vertex_properties.size(), 1u);
    EXPECT_EQ(m.vertex_properties[0].type, qsp::ScalarType::kInt16);
    ASSERT_EQ(m.face_properties.size(), 2u);
    EXPECT_TRUE(m.face_properties[0].list);
    EXPECT_EQ(m.comments, (std::vector<std::string>{"made by hand"}));
    const std::string out = qsp::write_ply_mesh(m);
    EXPECT_TRUE(out == bytes) << "differs at byte "
                              << std::mismatch(out.begin(), out.end(), bytes.begin(), bytes.end()).first -
                                     out.begin();
    // Through ASCII and back to binary: the same bytes again.
    const qsp::Mesh ascii = qsp::read_ply_mesh(qsp::write_ply_mesh(m, {.ply_keep_format = false}), "a.ply");
    EXPECT_EQ(ascii.ply.format, qsp::PlyFormat::kAscii);
    EXPECT_TRUE(qsp::write_ply_mesh(ascii, {.ply_format = m.ply.format, .ply_keep_format = false}) == bytes);
    EXPECT_EQ(qsp::testing::parse_ply_bytes(out).ply, qsp::testing::parse_ply_bytes(bytes).ply);
  }
}

// ---------------------------------------------------------------------------------------------
// Dropping, the QuadMesh bridge

TEST(MeshModel, DropSaysWhatItDroppedAndPositionsOnlyLeavesPositionsAndFaces) {
  QSP_NEEDS_SHARED();
  qsp::Mesh m = qsp::read_mesh((qsp::testing::shared_dir() / "meshes" / "mh_base.obj").string());
  const qsp::Extras before = qsp::extras(m);
  EXPECT_EQ(before.texcoords, 21334u);
  EXPECT_GT(before.groups, 100u);
  EXPECT_GT(before.comments, 10u);
  const qsp::Extras uv = qsp::drop(m, qsp::kCategoryUv);
  EXPECT_EQ(uv.texcoords, 21334u);
  EXPECT_EQ(uv.groups, 0u);
  EXPECT_TRUE(m.corner_texcoords.empty());
  ASSERT_NO_THROW(qsp::check_mesh(m));
  const qsp::Extras rest = qsp::drop(m, qsp::kCategoryAll);
  EXPECT_EQ(rest.groups, before.groups);
  EXPECT_FALSE(qsp::extras(m).any());
  ASSERT_NO_THROW(qsp::check_mesh(m));
  // Positions only: the QuadMesh reader's mesh, bit for bit.
  const qsp::QuadMesh q = qsp::to_quad_mesh(m);
  qsp::ReadReport report;
  const qsp::QuadMesh legacy =
      qsp::read_mesh_file((qsp::testing::shared_dir() / "meshes" / "mh_base.obj").string(), &report);
  EXPECT_EQ(q.quads, legacy.quads);
  EXPECT_TRUE(qsp::testing::same_bits(q.positions, legacy.positions));
  EXPECT_EQ(qsp::write_obj_mesh(m), qsp::write_obj(q));
}

TEST(MeshModel, QuadMeshBridgeAndChecks) {
  const qsp::Mesh tri = qsp::read_obj_mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n", "t.obj");
  const std::string msg = expect_error([&] { qsp::to_quad_mesh(tri); }, qsp::ErrorCode::kNotQuad);
  EXPECT_NE(msg.find("2 faces are not quads (first: face 0: triangle, face 1: triangle)"), std::string::npos)
      << msg;
  qsp::QuadMesh q;
  q.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  q.quads = {0, 1, 2, 3};
  const qsp::Mesh m = qsp::from_quad_mesh(q);
  EXPECT_EQ(m.face_offsets, (std::vector<std::uint32_t>{0, 4}));
  EXPECT_EQ(qsp::to_quad_mesh(m).quads, q.quads);
  // check_mesh names what is wrong.
  qsp::Mesh bad = m;
  bad.corner_vertices[2] = 0;
  EXPECT_NE(expect_error([&] { qsp::check_mesh(bad); }, qsp::ErrorCode::kUsage).find("repeats vertex 0"),
            std::string::npos);
  bad = m;
  bad.corner_texcoords = {0, 0, 0};
  expect_error([&] { qsp::check_mesh(bad); }, qsp::ErrorCode::kUsage);
  bad = m;
  bad.groups.face = {3};
  expect_error([&] { qsp::check_mesh(bad); }, qsp::ErrorCode::kUsage);
  bad = m;
  bad.statements = {{qsp::ObjStatement::kVertex, 3}, {qsp::ObjStatement::kFace, 1}};
  expect_error([&] { qsp::write_obj_mesh(bad); }, qsp::ErrorCode::kUsage);
  // The quad writers say the same of a partial array: the caller's mistake, not a bug in qsp.
  qsp::QuadMesh partial = q;
  partial.positions.pop_back();
  expect_error([&] { qsp::write_obj(partial); }, qsp::ErrorCode::kUsage);
  partial = q;
  partial.quads.pop_back();
  expect_error([&] { qsp::write_off(partial); }, qsp::ErrorCode::kUsage);
}

// The codec's PolygonMesh and back: every mesh of testdata/ (golden/'s subfolders of textured, labelled,
// tagged and normal files included) that carries what the codec keeps gives back its positions, faces,
// texture coordinates, normals, colours, labels, material libraries and tags, numbers bit for bit (their
// float64s too).
TEST(MeshModel, PolygonMeshBridgeGivesBackTheArrays) {
  constexpr unsigned kKept = qsp::kPolygonMeshCategories;
  int checked = 0;
  for (const auto& e : fs::recursive_directory_iterator(QSP_TESTDATA_DIR)) {
    const fs::path& p = e.path();
    if (p.extension() != ".obj" || p.string().find("invalid") != std::string::npos) continue;
    SCOPED_TRACE(p.string());
    qsp::Mesh m = qsp::read_mesh(p.string());
    if (!qsp::extras(m, kKept).any()) continue;
    // What to_polygon_mesh keeps, in the canonical order; these files' numbers are float32 or float64
    // (golden/exact: positions, texture coordinates, normals and colours float32 does not hold).
    qsp::drop(m, qsp::kCategoryAll & ~kKept);
    m.statements.clear();
    for (const qsp::Numbers* n : {&m.positions, &m.texcoords, &m.normals, &m.vertex_colors, &m.face_colors})
      ASSERT_NE(n->precision, qsp::Precision::kDecimal);
    const qsp::Mesh back = qsp::from_polygon_mesh(qsp::to_polygon_mesh(m, kKept));
    expect_same_mesh(m, back);
    ++checked;
    if (HasFailure()) break;  // one file's report is enough
  }
  EXPECT_GE(checked, 17);
}

// ---------------------------------------------------------------------------------------------
// Hostile input

// Byte and line edits of small files in each format: every outcome is a mesh that passes check_mesh
// and writes back to the same model, or a typed, non-internal error.
TEST(MeshHostile, MutantsGiveAMeshOrACleanError) {
  const std::vector<std::pair<qsp::MeshFormat, std::string>> bases = {
      {qsp::MeshFormat::kObj,
       "# c\nmtllib m\nv 0 0 0\nv 1 0 0 1 1 1\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\ng a b\nusemtl x\ns 1\n"
       "f 1/1/1 2/1/1 3/1/1 4/1/1\nf -4 -2 -1\nt crease 2/1/0 0 1 2.5\nvp 1\n"},
      {qsp::MeshFormat::kOff, "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3 1 0 0\n3 0 2 3 0 1 0\n"},
      {qsp::MeshFormat::kPly,
       "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
       "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 2\n"
       "property list uchar int vertex_indices\nproperty float q\nend_header\n"
       "0 0 0 1 2 3\n1 0 0 4 5 6\n1 1 0 7 8 9\n0 1 0 1 1 1\n4 0 1 2 3 0.5\n3 0 2 3 1e-3\n"},
  };
  const std::string alphabet = "vftgsuo #/\\-+.0123456789e\n\r\n\nxn";
  std::mt19937 rng(2025);
  int accepted = 0;
  for (const auto& [format, base] : bases) {
    for (int round = 0; round < 400; ++round) {
      std::string text = base;
      mutate(text, alphabet, rng);
      SCOPED_TRACE(text);
      qsp::Mesh m;
      try {
        m = read_text(text, format);
      } catch (const qsp::Error& e) {
        EXPECT_NE(e.code(), qsp::ErrorCode::kInternal) << e.what();
        continue;
      }
      ++accepted;
      ASSERT_NO_THROW(qsp::check_mesh(m));
      std::string out;
      try {
        out = qsp::write_mesh(m, format);
      } catch (const qsp::Error& e) {
        ADD_FAILURE() << "an accepted mesh does not write back: " << e.what();
        continue;
      }
      expect_same_mesh(m, read_text(out, format));
      if (HasFailure()) return;
    }
  }
  EXPECT_GT(accepted, 100);  // enough stay valid that the write-back is compared too
}

// Hostile sizes never allocate before the text shows them: a face of many corners, a header
// declaring far more than the file holds, a list longer than its bytes.
TEST(MeshHostile, LargeDeclarationsAndDegreesStayLinear) {
  std::string text;
  const int n = 200000;
  for (int i = 0; i < n; ++i) text.append("v ").append(std::to_string(i)).append(" 0 0\n");
  text += "f";
  for (int i = 1; i <= n; ++i) text.append(" ").append(std::to_string(i));
  text += " 7\n";  // repeats a vertex at the end: found without comparing every pair
  const std::string msg =
      expect_error([&] { qsp::read_obj_mesh(text, "big.obj"); }, qsp::ErrorCode::kDegenerateFace);
  EXPECT_NE(msg.find("face repeats vertex 7 (corners 7 and 200001)"), std::string::npos) << msg;
  expect_error([] { qsp::read_off_mesh("OFF\n1000000000 1 0\n0 0 0\n", "t.off"); }, qsp::ErrorCode::kParse);
  const std::string list_header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nproperty list uint float junk\nend_header\n";
  const std::string list = list_header + std::string(12, '\0') + std::string("\xff\xff\xff\x7f", 4);
  expect_error([&] { qsp::read_ply_mesh(list, "t.ply"); }, qsp::ErrorCode::kParse);
}

// fuzz_read_mesh: a binary PLY whose x is int and y, z float was refused on writing: the int check read
// y's and z's fractions too. Each column is checked alone; the mesh writes and reads back.
// A fuzzer finding: a header line ending in several CRs. Every CR before the LF ends the line, so a
// comment comes back as its text without them, and writing it again gives the same bytes.
TEST(MeshPly, HeaderLinesEndingInSeveralCrsReadAndWriteBackTheSame) {
  const std::string ply =
      "ply\r\nformat ascii 1.0\r\r\ncomment seed\r\r\r\nobj_info note\r\r\nelement vertex 3\nproperty float "
      "x\n"
      "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
      "end_header\r\r\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const qsp::Mesh m = qsp::read_ply_mesh(ply, "crs.ply");
  EXPECT_EQ(m.comments, std::vector<std::string>{"seed"});
  EXPECT_EQ(m.ply.obj_info, std::vector<std::string>{"note"});
  const std::string once = qsp::write_mesh(m, qsp::MeshFormat::kPly);
  EXPECT_EQ(qsp::write_mesh(qsp::read_ply_mesh(once, "once.ply"), qsp::MeshFormat::kPly), once);
}

TEST(MeshPly, AnIntegerColumnBesideFloatColumnsWritesAndReadsBack) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty int x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "-7 0.5 0.25\n3 0.5 1.5\n3 2.5 1.5\n-7 2.5 0.75\n4 0 1 2 3\n";
  const qsp::Mesh m = qsp::read_ply_mesh(ply, "int_x.ply");
  qsp::WriteOptions binary;
  binary.ply_format = qsp::PlyFormat::kBinaryLittleEndian;
  binary.ply_keep_format = false;
  for (const std::string& text :
       {qsp::write_mesh(m, qsp::MeshFormat::kPly), qsp::write_mesh(m, qsp::MeshFormat::kPly, binary)}) {
    EXPECT_NE(text.find("property int x"), std::string::npos);
    const qsp::Mesh back = qsp::read_ply_mesh(text, "back.ply");
    ASSERT_EQ(back.positions.size(), m.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i)
      EXPECT_EQ(back.positions.approx(i), m.positions.approx(i));
  }
  // A fraction in the int column itself is still refused.
  qsp::Mesh bad = m;
  for (auto* v : {&bad.positions.f32})
    if (!v->empty()) (*v)[0] = 0.5f;
  if (!bad.positions.f64.empty()) bad.positions.f64[0] = 0.5;
  EXPECT_THROW((void)qsp::write_mesh(bad, qsp::MeshFormat::kPly), qsp::Error);
}

// Every text finding in testdata/invalid/fuzz the exact readers accept (their `.expect` is the
// QuadMesh readers' and the codec's verdict) comes back unchanged from their own output, as
// fuzz_read_mesh checks: the same model, the same text.
TEST(MeshHostile, FuzzFindingsRoundTripAsMeshes) {
  const fs::path dir = fs::path(QSP_TESTDATA_DIR) / "invalid" / "fuzz";
  int checked = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    const fs::path f = e.path();
    const qsp::MeshFormat format = qsp::format_from_path(f.string());
    if (format != qsp::MeshFormat::kObj && format != qsp::MeshFormat::kOff && format != qsp::MeshFormat::kPly)
      continue;
    SCOPED_TRACE(f.filename().string());
    qsp::Mesh m;
    try {
      m = qsp::read_mesh(f.string());
    } catch (const qsp::Error& err) {
      EXPECT_NE(err.code(), qsp::ErrorCode::kInternal) << err.what();
      continue;
    }
    const std::string out = qsp::write_mesh(m, format);
    const qsp::Mesh back = read_text(out, format);
    expect_same_mesh(m, back);
    EXPECT_EQ(qsp::write_mesh(back, format), out);
    ++checked;
  }
  EXPECT_GE(checked, 6);
}
