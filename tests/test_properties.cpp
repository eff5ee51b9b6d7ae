// PLY vertex and face properties and OBJ vertex weights (the properties section, format 3.14), end to end:
// compress and decompress keep every value of every property with its name and type, read back by this
// test's own parsers (not qsp's readers): each vertex's values found by its position, each face's by its
// corners' positions; with --keep-order element for element. Renumbering gives the same bytes. Values
// float64 does not hold are refused (naming the property and --drop extra), and so is an output format
// that cannot hold them. The section's golden bytes are pinned, and every prefix, bit flip and cut of it
// is refused with a byte offset or decodes to properties that satisfy the section's rules.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
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
#include "support/minor.h"
#include "support/section_sweep.h"

namespace qsp {
namespace {

using testing::quote;
using testing::run_qsp;
using testing::slurp;
using testing::spit;

// ---- An independent PLY reader (ascii and binary little endian), enough for these tests ----

struct PlyProp {
  std::string type, name;  // type: "uchar", ..., or "list COUNT TYPE"
};
struct PlyFile {
  std::string format;
  std::vector<PlyProp> vertex_props, face_props;
  std::vector<std::array<double, 3>> positions;
  std::vector<std::map<std::string, std::vector<double>>> vertex, face;  // per element: name -> values
  std::vector<std::vector<std::size_t>> faces;
};

PlyFile parse_ply(const std::string& bytes) {
  PlyFile out;
  std::size_t at = 0;
  const auto line = [&] {
    const std::size_t end = bytes.find('\n', at);
    std::string l = bytes.substr(at, end - at);
    at = end + 1;
    return l;
  };
  std::string element;
  std::size_t nv = 0, nf = 0;
  for (std::string l = line(); l != "end_header"; l = line()) {
    std::istringstream s(l);
    std::string key;
    s >> key;
    if (key == "format") s >> out.format;
    if (key == "element") {
      std::size_t n = 0;
      s >> element >> n;
      (element == "vertex" ? nv : nf) = n;
    }
    if (key == "property") {
      PlyProp p;
      s >> p.type;
      if (p.type == "list") {
        std::string a, b;
        s >> a >> b;
        p.type = "list " + a + " " + b;
      }
      s >> p.name;
      (element == "vertex" ? out.vertex_props : out.face_props).push_back(p);
    }
  }
  const bool binary = out.format == "binary_little_endian";
  std::istringstream text(binary ? std::string() : bytes.substr(at));
  const auto read = [&](const std::string& type) -> double {
    if (!binary) {
      // A `float` is the binary32 its text denotes where binary32's shortest text of it denotes the same
      // value ("0.1"), else the text's nearest double ("0.123456789012345"), as qsp promises to keep it.
      std::string token;
      text >> token;
      const double d = std::strtod(token.c_str(), nullptr);
      if (type != "float") return d;
      const float f = std::strtof(token.c_str(), nullptr);
      char shortest[32];
      const auto end = std::to_chars(shortest, shortest + sizeof shortest, f).ptr;
      *end = 0;
      return std::strtod(shortest, nullptr) == d ? static_cast<double>(f) : d;
    }
    const auto take = [&](auto v) {
      std::memcpy(&v, bytes.data() + at, sizeof v);
      at += sizeof v;
      return static_cast<double>(v);
    };
    if (type == "uchar") return take(std::uint8_t{});
    if (type == "char") return take(std::int8_t{});
    if (type == "ushort") return take(std::uint16_t{});
    if (type == "short") return take(std::int16_t{});
    if (type == "uint") return take(std::uint32_t{});
    if (type == "int") return take(std::int32_t{});
    if (type == "float") return take(float{});
    return take(double{});
  };
  const auto values = [&](const PlyProp& p) {
    std::vector<double> v;
    if (!p.type.starts_with("list ")) return std::vector<double>{read(p.type)};
    std::istringstream t(p.type.substr(5));
    std::string count_type, type;
    t >> count_type >> type;
    v.resize(static_cast<std::size_t>(read(count_type)));
    for (double& x : v) x = read(type);
    return v;
  };
  for (std::size_t e = 0; e < nv; ++e) {
    std::array<double, 3> xyz{};
    auto& m = out.vertex.emplace_back();
    for (const PlyProp& p : out.vertex_props) {
      const std::vector<double> v = values(p);
      if (p.name == "x" || p.name == "y" || p.name == "z")
        xyz[static_cast<std::size_t>(p.name[0] - 'x')] = v[0];
      else
        m[p.name] = v;
    }
    out.positions.push_back(xyz);
  }
  for (std::size_t e = 0; e < nf; ++e) {
    auto& m = out.face.emplace_back();
    auto& corners = out.faces.emplace_back();
    for (const PlyProp& p : out.face_props) {
      const std::vector<double> v = values(p);
      if (p.name == "vertex_indices")
        for (const double c : v) corners.push_back(static_cast<std::size_t>(c));
      else
        m[p.name] = v;
    }
  }
  return out;
}

using Position = std::array<double, 3>;
using Values = std::map<std::string, std::vector<double>>;
// Each vertex's properties by its position; each face's by its corners' positions from the smallest.
std::map<Position, Values> by_position(const PlyFile& f) {
  std::map<Position, Values> out;
  for (std::size_t v = 0; v < f.positions.size(); ++v) out[f.positions[v]] = f.vertex[v];
  return out;
}
std::map<std::vector<Position>, Values> by_corners(const PlyFile& f) {
  std::map<std::vector<Position>, Values> out;
  for (std::size_t g = 0; g < f.faces.size(); ++g) {
    std::vector<Position> key;
    for (const std::size_t c : f.faces[g]) key.push_back(f.positions[c]);
    std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
    out[key] = f.face[g];
  }
  return out;
}
// Bit patterns, so that -0.0 and NaN compare as themselves.
std::vector<std::uint64_t> bits(const std::vector<double>& v) {
  std::vector<std::uint64_t> out;
  for (const double x : v) out.push_back(std::bit_cast<std::uint64_t>(x));
  return out;
}
void expect_same_values(const Values& a, const Values& b) {
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [name, v] : a) {
    ASSERT_TRUE(b.count(name)) << name;
    EXPECT_EQ(bits(v), bits(b.at(name))) << name;
  }
}

// A 3x2 grid of quads plus a triangle (a polygon mesh), with vertex properties of four kinds (uchar, float
// of more digits than binary32 holds, double, a list of ints) and face properties (int, a list of floats).
const char* const kPly =
    "ply\nformat ascii 1.0\ncomment made for qsp's tests\nelement vertex 13\nproperty float x\n"
    "property float y\nproperty float z\nproperty uchar flags\nproperty float quality\n"
    "property double confidence\nproperty list uchar int ids\nelement face 7\n"
    "property list uchar int vertex_indices\nproperty int label\nproperty list ushort float weights\n"
    "end_header\n"
    "0 0 0 1 0.5 0.1 0\n1 0 0 2 0.123456789012345 1e300 2 5 -6\n2 0 0 255 -3 -0.25 1 7\n"
    "3 0 0 0 1.5 2 0\n0 1 0 9 0.25 3 3 1 2 3\n1 1 0 4 0.75 4.000000000000001 0\n"
    "2 1 0 5 1 5 1 -2147483648\n3 1 0 6 2 6 0\n0 2 0 7 3 7 1 4294967\n1 2 0 8 4 8 0\n"
    "2 2 0 10 5 9 0\n3 2 0 11 6 10 2 1 1\n4 2.5 0 12 7 11 0\n"
    "4 0 1 5 4 -7 2 0.5 0.25\n4 1 2 6 5 2147483647 1 0.1\n4 2 3 7 6 0 0\n"
    "4 4 5 9 8 1 3 1 2 3\n4 5 6 10 9 2 0\n4 6 7 11 10 3 1 1e-30\n3 7 12 11 4 0\n";

class PropertiesCli : public testing::TempDirTest {
 protected:
  // compress IN (with FLAGS), decompress to OUT_EXT; both must succeed.
  void round_trip(const std::string& in, const std::string& flags, const std::string& out_ext) {
    auto r = run_qsp("compress -f " + flags + " " + quote(p(in)) + " " + quote(p("x.qsp")));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run_qsp("decompress -f " + quote(p("x.qsp")) + " -o " + quote(p("back" + out_ext)));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
};

TEST_F(PropertiesCli, PlyPropertiesComeBackValueForValueWithTheirNamesAndTypes) {
  spit(p("in.ply"), kPly);
  const PlyFile a = parse_ply(kPly);
  for (const std::string flags : {"", "--keep-order", "--best", "--fast"}) {
    SCOPED_TRACE(flags);
    round_trip("in.ply", flags, ".ply");
    const PlyFile b = parse_ply(slurp(p("back.ply")));
    // The same properties in the same order with the same types, but where binary PLY widens a float
    // property holding a value of more digits than binary32 (quality) to double.
    EXPECT_EQ(b.vertex_props.size(), a.vertex_props.size());
    for (std::size_t i = 0; i < std::min(a.vertex_props.size(), b.vertex_props.size()); ++i)
      EXPECT_EQ(b.vertex_props[i].type + " " + b.vertex_props[i].name,
                (a.vertex_props[i].name == "quality" ? "double" : a.vertex_props[i].type) + " " +
                    a.vertex_props[i].name);
    ASSERT_EQ(b.face_props.size(), a.face_props.size());
    for (std::size_t i = 1; i < a.face_props.size(); ++i)  // vertex_indices: the writer's index type
      EXPECT_EQ(b.face_props[i].type + " " + b.face_props[i].name,
                a.face_props[i].type + " " + a.face_props[i].name);
    const auto va = by_position(a), vb = by_position(b);
    ASSERT_EQ(va.size(), vb.size());
    for (const auto& [at, values] : va) {
      ASSERT_TRUE(vb.count(at));
      expect_same_values(values, vb.at(at));
    }
    const auto fa = by_corners(a), fb = by_corners(b);
    ASSERT_EQ(fa.size(), fb.size());
    for (const auto& [at, values] : fa) {
      ASSERT_TRUE(fb.count(at));
      expect_same_values(values, fb.at(at));
    }
    if (flags == "--keep-order") {  // element for element
      EXPECT_EQ(b.positions, a.positions);
      EXPECT_EQ(b.faces, a.faces);
      for (std::size_t v = 0; v < a.vertex.size(); ++v) expect_same_values(a.vertex[v], b.vertex[v]);
    }
    const auto s = run_qsp("stats --json " + quote(p("x.qsp")));
    const std::string minor =
        std::to_string(testing::minor_of_file_with(slurp(p("x.qsp")), kFormatMinorProperties));
    EXPECT_NE(s.out.find("\"format\": \"3." + minor + "\""), std::string::npos) << s.out;
    EXPECT_EQ(s.out.find("\"properties\": 0,"), std::string::npos) << s.out;
  }
}

// Binary input: every value bit for bit in its declared type (a double of any bits, a float's binary32),
// and an all-quad mesh (the quad path).
TEST_F(PropertiesCli, BinaryPlyPropertiesComeBackBitForBit) {
  std::string text =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nproperty double value\nproperty short s\nelement face 1\n"
      "property list uchar int vertex_indices\nproperty float area\nend_header\n";
  const auto put = [&](auto v) { text.append(reinterpret_cast<const char*>(&v), sizeof v); };
  const double values[] = {0.1, -1e-310, 3.141592653589793, std::nextafter(1.0, 2.0)};
  for (int v = 0; v < 4; ++v) {
    put(static_cast<float>(v & 1));
    put(static_cast<float>(v >> 1));
    put(0.0f);
    put(values[v]);
    put(static_cast<std::int16_t>(-300 * v));
  }
  put(std::uint8_t{4});
  for (const std::int32_t c : {0, 1, 3, 2}) put(c);
  put(0.3f);
  spit(p("in.ply"), text);
  round_trip("in.ply", "", ".ply");
  const PlyFile a = parse_ply(text), b = parse_ply(slurp(p("back.ply")));
  const auto va = by_position(a), vb = by_position(b);
  for (const auto& [at, v] : va) expect_same_values(v, vb.at(at));
  expect_same_values(a.face[0], b.face[0]);
  EXPECT_EQ(b.vertex_props[3].type, "double");
  EXPECT_EQ(b.vertex_props[4].type, "short");
}

// OBJ `v x y z w`: each weight the same double (text of more digits than binary32 holds included), in
// the same v lines with --keep-order.
TEST_F(PropertiesCli, ObjVertexWeightsComeBackAsTheSameDoubles) {
  std::string obj;
  const char* const weights[] = {"1",   "0.5", "0.123456789012345", "2.5e-7", "123456.78901234567", "-0", "7",
                                 "0.1", "3"};
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x)
      obj += "v " + std::to_string(x) + " " + std::to_string(y) + " 0 " + weights[3 * y + x] + "\n";
  obj += "f 1 2 5 4\nf 2 3 6 5\nf 4 5 8 7\nf 5 6 9 8\n";
  spit(p("in.obj"), obj);
  const auto weights_of = [](const std::string& text) {
    std::map<Position, std::uint64_t> out;
    std::vector<Position> order;
    std::istringstream s(text);
    for (std::string l; std::getline(s, l);) {
      if (!l.starts_with("v ")) continue;
      std::istringstream t(l.substr(2));
      std::string x, y, z, w;
      t >> x >> y >> z >> w;
      const Position at{std::strtod(x.c_str(), nullptr), std::strtod(y.c_str(), nullptr),
                        std::strtod(z.c_str(), nullptr)};
      out[at] = std::bit_cast<std::uint64_t>(std::strtod(w.c_str(), nullptr));
      order.push_back(at);
    }
    return std::pair{out, order};
  };
  for (const std::string flags : {"", "--keep-order"}) {
    SCOPED_TRACE(flags);
    round_trip("in.obj", flags, ".obj");
    const auto a = weights_of(obj), b = weights_of(slurp(p("back.obj")));
    EXPECT_EQ(b.first, a.first);
    if (!flags.empty()) {
      EXPECT_EQ(b.second, a.second);
    }
  }
}

// Canonical: vertices and faces renumbered and corners rotated, the same bytes.
TEST_F(PropertiesCli, RenumberingGivesTheSameBytes) {
  const PlyFile a = parse_ply(kPly);
  const std::size_t nv = a.positions.size(), nf = a.faces.size();
  std::vector<std::size_t> vorder(nv), forder(nf);
  for (std::size_t i = 0; i < nv; ++i) vorder[i] = (7 * i + 3) % nv;  // 13 is prime: a permutation
  for (std::size_t i = 0; i < nf; ++i) forder[i] = nf - 1 - i;
  std::vector<std::size_t> new_of(nv);
  for (std::size_t i = 0; i < nv; ++i) new_of[vorder[i]] = i;
  // The ascii data lines, vertex lines then face lines, taken from kPly itself.
  std::vector<std::string> lines;
  std::istringstream s(kPly);
  std::string header;
  for (std::string l; std::getline(s, l);) {
    header += l + "\n";
    if (l == "end_header") break;
  }
  for (std::string l; std::getline(s, l);) lines.push_back(l);
  std::string text = header;
  for (std::size_t i = 0; i < nv; ++i) text += lines[vorder[i]] + "\n";
  for (std::size_t i = 0; i < nf; ++i) {
    std::istringstream t(lines[nv + forder[i]]);
    std::size_t d = 0;
    t >> d;
    std::vector<std::size_t> c(d);
    for (std::size_t& x : c) t >> x;
    std::string rest;
    std::getline(t, rest);
    std::rotate(c.begin(), c.begin() + 1, c.end());
    text += std::to_string(d);
    for (const std::size_t x : c) {
      text += ' ';
      text += std::to_string(new_of[x]);
    }
    text += rest + "\n";
  }
  spit(p("a.ply"), kPly);
  spit(p("b.ply"), text);
  for (const std::string flags : {"", "--best"}) {
    SCOPED_TRACE(flags);
    ASSERT_EQ(run_qsp("compress -f " + flags + " " + quote(p("a.ply")) + " " + quote(p("a.qsp"))).exit_code,
              0);
    ASSERT_EQ(run_qsp("compress -f " + flags + " " + quote(p("b.ply")) + " " + quote(p("b.qsp"))).exit_code,
              0);
    EXPECT_EQ(slurp(p("a.qsp")), slurp(p("b.qsp")));
  }
}

// reorder --like REF IN: IN's properties, each with its vertex or face, in REF's order.
TEST_F(PropertiesCli, ReorderKeepsThemWithTheirVerticesAndFaces) {
  spit(p("in.ply"), kPly);
  round_trip("in.ply", "", ".ply");  // back.ply: the same mesh, renumbered canonically
  const auto r = run_qsp("reorder --like " + quote(p("back.ply")) + " " + quote(p("in.ply")) + " -o " +
                         quote(p("r.ply")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const PlyFile ref = parse_ply(slurp(p("back.ply"))), in = parse_ply(kPly),
                out = parse_ply(slurp(p("r.ply")));
  EXPECT_EQ(out.positions, ref.positions);
  EXPECT_EQ(out.faces, ref.faces);
  const auto va = by_position(in), vb = by_position(out);
  for (const auto& [at, values] : va) expect_same_values(values, vb.at(at));
  const auto fa = by_corners(in), fb = by_corners(out);
  for (const auto& [at, values] : fa) expect_same_values(values, fb.at(at));
}

TEST_F(PropertiesCli, ValuesFloat64DoesNotHoldAreRefusedUnlessDropped) {
  std::string text = kPly;
  const std::size_t at = text.find("0.123456789012345");
  text.replace(at, 17, "0.12345678901234567891");
  spit(p("in.ply"), text);
  auto r = run_qsp("compress -f " + quote(p("in.ply")) + " " + quote(p("x.qsp")));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("PLY vertex property 'quality'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--drop extra"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(p("x.qsp")));
  r = run_qsp("compress -f --drop extra " + quote(p("in.ply")) + " " + quote(p("x.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("dropped"), std::string::npos) << r.err;
  EXPECT_EQ(decode_polygons(slurp(p("x.qsp"))).vertex_properties.size(), 0u);
}

TEST_F(PropertiesCli, AnOutputThatCannotHoldThemIsRefused) {
  spit(p("in.ply"), kPly);
  ASSERT_EQ(run_qsp("compress -f " + quote(p("in.ply")) + " " + quote(p("x.qsp"))).exit_code, 0);
  for (const std::string ext : {".obj", ".off"}) {
    const auto r = run_qsp("decompress -f " + quote(p("x.qsp")) + " -o " + quote(p("back" + ext)));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("PLY properties"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(p("back" + ext)));
  }
}

// PLY obj_info header lines (format 3.15's optional section): kept in order, written back to PLY, refused
// by OBJ, dropped with extra; a broken section is a format error naming the byte offset.
TEST_F(PropertiesCli, PlyObjInfoLinesComeBackInOrder) {
  std::string text = kPly;
  text.insert(text.find("element vertex"), "obj_info scanned 2026-12-04\nobj_info  two  spaces\n");
  spit(p("in.ply"), text);
  round_trip("in.ply", "", ".ply");
  const std::string back = slurp(p("back.ply"));
  EXPECT_NE(back.find("\nobj_info scanned 2026-12-04\nobj_info  two  spaces\n"), std::string::npos) << back;
  EXPECT_EQ(slurp(p("x.qsp"))[9], testing::minor_of_file_with(slurp(p("x.qsp")), kFormatMinorPlyInfo));
  auto r = run_qsp("decompress -f " + quote(p("x.qsp")) + " -o " + quote(p("back.obj")));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("obj_info"), std::string::npos) << r.err;
  r = run_qsp("compress -f --drop extra " + quote(p("in.ply")) + " " + quote(p("x.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(decode_polygons(slurp(p("x.qsp"))).ply_info.empty());
  for (const auto& [payload, what] : {std::pair<std::string, const char*>{std::string(1, '\0'), "line count"},
                                      {std::string("\x01\x02"
                                                   "a\n",
                                                   4),
                                       "line break"},
                                      {std::string("\x01\x01"
                                                   "ab",
                                                   4),
                                       "after the last line"}}) {
    SCOPED_TRACE(what);
    try {
      (void)decode_ply_info_section(payload, 50);
      ADD_FAILURE() << "decoded";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kFormat);
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("byte offset 5"), std::string::npos) << e.what();
    }
  }
}

// ---- The section itself ----

const std::string kGoldenDir = std::string(QSP_TESTDATA_DIR) + "/golden/properties";

PolygonMesh read_golden_ply(const std::string& path) {
  return to_polygon_mesh(read_ply_mesh(slurp(path), path), kPolygonMeshCategories | kCategoryExtra);
}

EncodeOptions golden_options() {
  EncodeOptions o;
  o.level = kMaxLevel;
  o.partition = PartitionMode::kMotorcycle;
  return o;
}

// Each testdata/golden/properties/NAME.ply as qsp compresses it at --best on the motorcycle graph:
// pinned bytes, a 3.14 file, and decoded to the same properties (by vertex position).
TEST(PropertiesGolden, BytesArePinnedAndDecodeToTheSameValues) {
  int seen = 0;
  for (const auto& e : std::filesystem::directory_iterator(kGoldenDir)) {
    if (e.path().extension() != ".ply") continue;
    ++seen;
    const std::string ply = e.path().string(),
                      qsp = e.path().parent_path() / (e.path().stem().string() + ".qsp");
    SCOPED_TRACE(ply);
    const PolygonMesh mesh = read_golden_ply(ply);
    const std::string bytes = encode_polygons(mesh, golden_options());
    const char* update = std::getenv("QSP_UPDATE_GOLDEN");
    if (update && std::string(update) == "1") spit(qsp, bytes);
    EXPECT_EQ(bytes, slurp(qsp)) << "the encoder's output changed: a format change needs a version bump";
    EXPECT_EQ(bytes[9], kFormatMinorProperties);
    const PolygonMesh back = decode_polygons(bytes);
    ASSERT_EQ(back.vertex_properties.size(), mesh.vertex_properties.size());
    ASSERT_EQ(back.face_properties.size(), mesh.face_properties.size());
    std::map<std::array<float, 3>, std::size_t> at;
    for (std::size_t v = 0; v < back.vertex_count(); ++v)
      at[{back.positions[3 * v], back.positions[3 * v + 1], back.positions[3 * v + 2]}] = v;
    for (std::size_t i = 0; i < mesh.vertex_properties.size(); ++i) {
      const ValueProperty &a = mesh.vertex_properties[i], &b = back.vertex_properties[i];
      EXPECT_EQ(b.name, a.name);
      EXPECT_EQ(b.type, a.type);
      EXPECT_EQ(b.list, a.list);
      for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        const std::size_t w =
            at.at({mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]});
        const auto values = [](const ValueProperty& p, std::size_t k) {
          return p.list ? std::vector<double>(p.values.begin() + p.offsets[k],
                                              p.values.begin() + p.offsets[k + 1])
                        : std::vector<double>{p.values[k]};
        };
        EXPECT_EQ(bits(values(b, w)), bits(values(a, v))) << a.name << " of vertex " << v;
      }
    }
  }
  EXPECT_GE(seen, 1);
}

TEST(PropertiesGolden, EveryPrefixBitFlipAndCutIsSafe) {
  const std::string good = slurp(kGoldenDir + "/scan_polygons.qsp");
  const int decoded =
      testing::sweep_section(good, container::kTagProperties, good[9], [](const PolygonMesh& got) {
        for (const auto* props : {&got.vertex_properties, &got.face_properties})
          for (const ValueProperty& p : *props) {
            ASSERT_EQ(p.list ? p.offsets.size() - 1 : p.values.size(),
                      props == &got.vertex_properties ? got.vertex_count() : got.face_count());
            for (const char c : p.name) ASSERT_TRUE(c > ' ' && c <= '~');
          }
      });
  EXPECT_GT(decoded, 0) << "some flips change a value to another valid value";
}

// Hand-made payloads breaking one rule each: a format error naming the byte offset, before any allocation
// the bytes cannot back.
TEST(PropertiesSection, BrokenRulesAreFormatErrors) {
  const auto payload = [](std::initializer_list<int> b) {
    std::string s;
    for (const int x : b) s.push_back(static_cast<char>(x));
    return s;
  };
  const std::pair<std::string, const char*> cases[] = {
      {payload({0}), "property count"},
      {payload({0x7f, 0, 6, 0}), "property count"},                          // more than the bytes back
      {payload({1, 0x08, 6, 1, 'q', 0, 0, 0, 0}), "reserved flag"},          // reserved flag bit
      {payload({1, 0, 9, 1, 'q', 0, 0, 0, 0}), "type byte"},                 // value type 9
      {payload({1, 0, 0x16, 1, 'q', 0, 0, 0, 0}), "type byte"},              // a scalar with a length type
      {payload({1, 0, 1, 1, 'q', 0x80, 0x04}), "integer type"},              // uchar 256
      {payload({1, 1, 6, 0, 0, 0, 0, 0}), "no name"},                        // empty name on a face property
      {payload({1, 0, 6, 1, ' ', 0, 0, 0, 0}), "name"},                      // a space in the name
      {payload({1, 4, 1, 1, 'q', 0}), "binary64"},                           // binary64 on an integer type
      {payload({1, 2, 0x11, 1, 'q', 0x7f}), "values"},                       // 127 values, no bytes
      {payload({2, 1, 1, 1, 'f', 0, 0, 1, 'v', 0}), "after a face"},         // vertex after face
      {payload({2, 0, 1, 1, 'q', 0, 0, 1, 1, 'q', 0}), "earlier property"},  // two of one name
      {payload({1, 0, 1, 1, 'q', 0, 0}), "after the last"},                  // a byte left over
  };
  // 65,537 properties in bytes enough for them: over the format's limit, refused before any is read.
  std::vector<std::pair<std::string, const char*>> all(std::begin(cases), std::end(cases));
  all.emplace_back(payload({0x81, 0x80, 0x04}) + std::string(3 * 65537, '\0'), "limit");
  for (const auto& [bytes, what] : all) {
    SCOPED_TRACE(what);
    try {
      (void)decode_properties_section(bytes, 100, 1, 1);
      ADD_FAILURE() << "decoded";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kFormat);
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("byte offset 10"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace qsp
