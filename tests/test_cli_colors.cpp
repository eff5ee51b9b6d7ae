// Colours end to end (compress, decompress): OBJ `v x y z r g b [a]`, OFF vertex and face colours and PLY
// colour properties come back value for value, read back by this test's own parsers (not qsp's readers):
// each vertex's colour found by its position, each face's by its corners' positions; PLY colours stay
// uchar. Colour text float32 does not hold is kept as float64 (float64's refused unless --float32 or
// --drop color, naming the value); a format that cannot hold what the file has (face colours in OBJ) is
// refused with no output.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli.h"
#include "support/minor.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::run_qsp;
using testing::slurp;
using testing::spit;

using Position = std::array<double, 3>;
struct Parsed {
  std::map<Position, std::vector<double>> vertex;                  // colour by position
  std::multimap<std::vector<Position>, std::vector<double>> face;  // colour by corners from the smallest
  std::size_t vertices = 0, faces = 0;
};

std::vector<Position> face_key(const std::vector<Position>& at, const std::vector<std::size_t>& corners) {
  std::vector<Position> key;
  for (std::size_t c : corners) key.push_back(at.at(c));
  std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
  return key;
}

// OBJ `v x y z [colour...]` and `f a b c ...` (indices from 1, no slashes in these tests).
Parsed parse_obj(const std::string& text) {
  Parsed out;
  std::vector<Position> at;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream l(line);
    std::string key;
    l >> key;
    if (key == "v") {
      Position p;
      l >> p[0] >> p[1] >> p[2];
      std::vector<double> colour;
      for (std::string x; l >> x;) colour.push_back(std::strtod(x.c_str(), nullptr));
      at.push_back(p);
      out.vertex[p] = colour;
    } else if (key == "f") {
      std::vector<std::size_t> corners;
      for (std::size_t i; l >> i;) corners.push_back(i - 1);
      out.face.emplace(face_key(at, corners), std::vector<double>{});
    }
  }
  out.vertices = at.size();
  out.faces = out.face.size();
  return out;
}

// OFF: header, counts, vertices with `vc` colour numbers, faces with theirs after the indices.
Parsed parse_off(const std::string& text, std::size_t vc) {
  Parsed out;
  std::istringstream in(text);
  std::string header;
  in >> header;
  std::size_t nv = 0, nf = 0, ne = 0;
  in >> nv >> nf >> ne;
  std::vector<Position> at(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    in >> at[v][0] >> at[v][1] >> at[v][2];
    std::vector<double> colour(vc);
    for (double& x : colour) in >> x;
    out.vertex[at[v]] = colour;
  }
  std::string rest;
  std::getline(in, rest);
  for (std::size_t f = 0; f < nf; ++f) {
    std::getline(in, rest);
    std::istringstream l(rest);
    std::size_t d = 0;
    l >> d;
    std::vector<std::size_t> corners(d);
    for (std::size_t& c : corners) l >> c;
    std::vector<double> colour;
    for (double x; l >> x;) colour.push_back(x);
    out.face.emplace(face_key(at, corners), colour);
  }
  out.vertices = nv;
  out.faces = nf;
  return out;
}

// PLY (ascii or binary little endian) with scalar vertex properties and a face list `vertex_indices`
// followed by scalar properties; `types` receives each property's "element.name" -> type.
Parsed parse_ply(const std::string& bytes, std::map<std::string, std::string>& types) {
  Parsed out;
  std::size_t at = 0;
  const auto line = [&] {
    const std::size_t end = bytes.find('\n', at);
    std::string l = bytes.substr(at, end - at);
    at = end + 1;
    return l;
  };
  std::string format, element;
  std::size_t nv = 0, nf = 0;
  std::vector<std::pair<std::string, std::string>> vprops, fprops;  // (type, name); list: ("list T I", ...)
  for (std::string l = line(); l != "end_header"; l = line()) {
    std::istringstream s(l);
    std::string key;
    s >> key;
    if (key == "format") s >> format;
    if (key == "element") {
      std::size_t n = 0;
      s >> element >> n;
      (element == "vertex" ? nv : nf) = n;
    }
    if (key == "property") {
      std::string type, a, b, name;
      s >> type;
      if (type == "list") {
        s >> a >> b >> name;
        type = "list " + a + " " + b;
      } else {
        s >> name;
      }
      (element == "vertex" ? vprops : fprops).push_back({type, name});
      types[element + "." + name] = type;
    }
  }
  const bool binary = format == "binary_little_endian";
  std::istringstream text(binary ? std::string() : bytes.substr(at));
  const auto read = [&](const std::string& type) -> double {
    if (!binary) {
      double x;
      text >> x;
      return x;
    }
    const auto take = [&](auto v) {
      std::memcpy(&v, bytes.data() + at, sizeof v);
      at += sizeof v;
      return static_cast<double>(v);
    };
    if (type == "uchar" || type == "uint8") return take(std::uint8_t{});
    if (type == "char" || type == "int8") return take(std::int8_t{});
    if (type == "ushort" || type == "uint16") return take(std::uint16_t{});
    if (type == "short" || type == "int16") return take(std::int16_t{});
    if (type == "uint" || type == "uint32") return take(std::uint32_t{});
    if (type == "int" || type == "int32") return take(std::int32_t{});
    if (type == "float" || type == "float32") return take(float{});
    return take(double{});
  };
  std::vector<Position> positions(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    std::vector<double> colour;
    for (const auto& [type, name] : vprops) {
      const double x = read(type);
      if (name == "x") positions[v][0] = x;
      if (name == "y") positions[v][1] = x;
      if (name == "z") positions[v][2] = x;
      if (name == "red" || name == "green" || name == "blue" || name == "alpha") colour.push_back(x);
    }
    out.vertex[positions[v]] = colour;
  }
  for (std::size_t f = 0; f < nf; ++f) {
    std::vector<std::size_t> corners;
    std::vector<double> colour;
    for (const auto& [type, name] : fprops) {
      if (type.starts_with("list ")) {
        std::istringstream t(type.substr(5));
        std::string count_type, index_type;
        t >> count_type >> index_type;
        corners.resize(static_cast<std::size_t>(read(count_type)));
        for (std::size_t& c : corners) c = static_cast<std::size_t>(read(index_type));
      } else {
        colour.push_back(read(type));
      }
    }
    out.face.emplace(face_key(positions, corners), colour);
  }
  out.vertices = nv;
  out.faces = nf;
  return out;
}

class ColorsCli : public testing::TempDirTest {
 protected:
  void round_trip(const std::string& name, const std::string& text, const std::string& out_ext,
                  const std::string& flags = "") {
    spit(p(name), text);
    auto r = run_qsp("compress -f " + flags + " " + quote(p(name)) + " " + quote(p("x.qsp")));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run_qsp("decompress -f " + quote(p("x.qsp")) + " -o " + quote(p("back" + out_ext)));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run_qsp("stats " + quote(p("x.qsp")));
    EXPECT_NE(r.out.find("format 3." + std::to_string(testing::minor_of_file_with(slurp(p("x.qsp")), 8))),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find(" colours"), std::string::npos) << r.out;
  }
};

TEST_F(ColorsCli, ObjVertexColoursComeBackValueForValue) {
  std::string text;
  int k = 0;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x, ++k)
      text += "v " + std::to_string(x) + " " + std::to_string(y) + " 0 0." + std::to_string(k % 10) + "25 " +
              std::to_string(k * 0.0625) + " 1\n";
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) {
      const int a = 4 * y + x + 1;
      text += "f " + std::to_string(a) + " " + std::to_string(a + 1) + " " + std::to_string(a + 5) + " " +
              std::to_string(a + 4) + "\n";
    }
  const std::string three = text;
  for (const std::string& flags : {std::string(), std::string("--keep-order"), std::string("--best")}) {
    SCOPED_TRACE(flags);
    round_trip("in.obj", three, ".obj", flags);
    const Parsed a = parse_obj(three), b = parse_obj(slurp(p("back.obj")));
    EXPECT_EQ(b.vertices, a.vertices);
    EXPECT_EQ(b.vertex, a.vertex);
    EXPECT_EQ(b.face, a.face);
    if (flags == "--keep-order") {  // the same vertices in the same order
      std::istringstream x(three), y(slurp(p("back.obj")));
      std::vector<Position> first, second;
      for (std::string l; std::getline(x, l);)
        if (l.starts_with("v ")) first.push_back(parse_obj(l).vertex.begin()->first);
      for (std::string l; std::getline(y, l);)
        if (l.starts_with("v ")) second.push_back(parse_obj(l).vertex.begin()->first);
      EXPECT_EQ(first, second);
    }
  }
}

TEST_F(ColorsCli, OffVertexAndFaceColoursComeBackValueForValue) {
  const std::string text =
      "COFF\n6 3 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n0 1 0 9 9 9 128\n2 0 0 1 2 3 4\n"
      "2 1 0 5 6 7 8\n4 0 1 2 3 0.25 0.5 0.75\n3 1 4 5 0.125 1 0\n3 1 5 2 1 0.5 0\n";
  round_trip("in.off", text, ".off");
  const Parsed a = parse_off(text, 4), b = parse_off(slurp(p("back.off")), 4);
  EXPECT_EQ(b.vertex, a.vertex);
  EXPECT_EQ(b.face, a.face);
  // OBJ has no face colours: refused, naming them and how to drop them, and nothing written.
  const auto r = run_qsp("decompress -f " + quote(p("x.qsp")) + " -o " + quote(p("back.obj")));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("face colours"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("back.obj")));
}

TEST_F(ColorsCli, PlyColoursStayBytesThroughBinaryPly) {
  std::string text =
      "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 2\n"
      "property list uchar int vertex_indices\nproperty uchar red\nproperty uchar green\nproperty uchar "
      "blue\n"
      "end_header\n0 0 0 10 20 30\n1 0 0 40 50 60\n1 1 0 70 80 90\n0 1 0 0 0 0\n2 0 0 255 255 255\n"
      "4 0 1 2 3 1 2 3\n3 1 4 2 200 100 0\n";
  round_trip("in.ply", text, ".ply");
  std::map<std::string, std::string> in_types, out_types;
  const Parsed a = parse_ply(text, in_types), b = parse_ply(slurp(p("back.ply")), out_types);
  EXPECT_EQ(b.vertex, a.vertex);
  EXPECT_EQ(b.face, a.face);
  for (const char* c : {"vertex.red", "vertex.green", "vertex.blue", "face.red", "face.green", "face.blue"})
    EXPECT_EQ(out_types[c], "uchar") << c;
  EXPECT_NE(slurp(p("back.ply")).find("format binary_little_endian 1.0"), std::string::npos);
}

TEST_F(ColorsCli, ColourTextFloat32DoesNotHoldIsKeptUnlessRoundedOrDropped) {
  const std::string text =
      "v 0 0 0 0.1234567891 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\nf 1 2 3 4\n";
  spit(p("in.obj"), text);
  auto r = run_qsp("compress -f " + quote(p("in.obj")) + " " + quote(p("x.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_qsp("decompress -f " + quote(p("x.qsp")) + " -o " + quote(p("back.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(slurp(p("back.obj")).find(" 0.1234567891 0 0\n"), std::string::npos) << slurp(p("back.obj"));
  // More digits than float64 holds: refused unless rounded, naming the value.
  spit(p("wide.obj"),
       "v 0 0 0 0.12345678901234567890123 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\n"
       "f 1 2 3 4\n");
  r = run_qsp("compress -f " + quote(p("wide.obj")) + " " + quote(p("w.qsp")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("vertex colour 0 (OBJ `v` 1) has 1.2345678901234567890123e-1"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("--drop color"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("w.qsp")));
  r = run_qsp("compress -f --float32 " + quote(p("in.obj")) + " " + quote(p("x.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("rounded 1 colour values to float32"), std::string::npos) << r.err;
  r = run_qsp("compress -f --drop color " + quote(p("in.obj")) + " " + quote(p("y.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("dropped 4 vertex colours"), std::string::npos) << r.err;
  r = run_qsp("stats " + quote(p("y.qsp")));
  EXPECT_EQ(r.out.find(" colours"), std::string::npos) << r.out;
}

TEST_F(ColorsCli, QuantizedColoursAreOnTheirGrid) {
  const std::string text =
      "v 0 0 0 0.101 0.202 0.303\nv 1 0 0 0.404 0.505 0.606\nv 1 1 0 0.707 0.808 0.909\nv 0 1 0 1 0 0.333\n"
      "f 1 2 3 4\n";  // three decimals: finer than 2^-6, so rounded
  round_trip("in.obj", text, ".obj", "--quantize-color 6");
  const Parsed a = parse_obj(text), b = parse_obj(slurp(p("back.obj")));
  ASSERT_EQ(b.vertex.size(), a.vertex.size());
  for (const auto& [at, colour] : a.vertex) {
    ASSERT_EQ(b.vertex.at(at).size(), colour.size());
    for (std::size_t c = 0; c < colour.size(); ++c) {
      const double y = b.vertex.at(at)[c];
      EXPECT_LE(std::fabs(y - colour[c]), 1.0 / 128 + 1e-7);
      EXPECT_EQ(y * 64, std::round(y * 64)) << y;
    }
  }
}

// reorder --like keeps IN's colours, texture coordinates, groups, materials and tags in REF's order: a
// hand-checked case (IN is REF's two quads with vertices, faces and corners shuffled).
TEST_F(ColorsCli, ReorderKeepsEveryAttributeInTheReferencesOrder) {
  spit(p("ref.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 5 6 3\n");
  spit(p("in.obj"),
       "v 2 1 0 0.6 0.6 0.6\nv 1 1 0 0.3 0.3 0.3\nv 0 0 0 0.1 0.1 0.1\nv 2 0 0 0.5 0.5 0.5\n"
       "v 1 0 0 0.2 0.2 0.2\nv 0 1 0 0.4 0.4 0.4\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
       "g right\nusemtl red\nf 5/1 4/2 1/3 2/4\ng left\nusemtl blue\nf 2/5 6/4 3/1 5/2\n"
       "t crease 2/1/0 4 0 3.5\n");
  auto r = run_qsp("reorder --like " + quote(p("ref.obj")) + " " + quote(p("in.obj")) + " -o " +
                   quote(p("out.obj")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // REF's vertices and faces, each vertex with IN's colour at its position, each corner with the texture
  // coordinate IN's corner at that position named, the crease between the same two positions.
  EXPECT_EQ(slurp(p("out.obj")),
            "v 0 0 0 0.1 0.1 0.1\nv 1 0 0 0.2 0.2 0.2\nv 1 1 0 0.3 0.3 0.3\nv 0 1 0 0.4 0.4 0.4\n"
            "v 2 0 0 0.5 0.5 0.5\nv 2 1 0 0.6 0.6 0.6\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
            "g left\nusemtl blue\nf 1/1 2/2 3/5 4/4\ng right\nusemtl red\nf 2/1 5/2 6/3 3/4\n"
            "t crease 2/1/0 1 5 3.5\n");
  // Into a .qsp the order is kept: decompressing gives the same text.
  r = run_qsp("reorder --like " + quote(p("ref.obj")) + " " + quote(p("in.obj")) + " -o " +
              quote(p("out.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_qsp("decompress -c " + quote(p("out.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, slurp(p("out.obj")));
  // A tag qsp cannot renumber cannot follow the vertices: refused, naming it and --drop tag.
  spit(p("edit.obj"), slurp(p("in.obj")) + "t vertexedit 1/0/0 3\n");
  r = run_qsp("reorder --like " + quote(p("ref.obj")) + " " + quote(p("edit.obj")) + " -o " +
              quote(p("e.obj")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("'vertexedit') indexes what qsp cannot renumber"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--drop tag"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("e.obj")));
}

// What the review of the colours work found, each fixed: reorder's quad path wrote OBJ text into OUT.ply;
// reorder to OBJ would put labelled faces out of REF's order; binary PLY doubles that are float32 values
// were refused as rounded; --drop did not apply to a .qsp IN; PLY got a lone `red` for OFF's colour-map
// indices; float colours of 0 and 1 became uchar (near black).
TEST_F(ColorsCli, WhatTheReviewFound) {
  spit(p("sq.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 5 6 3\n");
  auto r =
      run_qsp("reorder --like " + quote(p("sq.obj")) + " " + quote(p("sq.obj")) + " -o " + quote(p("q.ply")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(slurp(p("q.ply")).substr(0, 4), "ply\n");
  EXPECT_EQ(run_qsp("compress -f " + quote(p("q.ply"))).exit_code, 0);
  // The second face in REF's order has no group, the first has one: OBJ cannot say that.
  spit(p("ref.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 2 5 6 3\nf 1 2 3 4\n");
  spit(p("in.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 1 2 3 4\ng a\nf 2 5 6 3\n");
  r = run_qsp("reorder --like " + quote(p("ref.obj")) + " " + quote(p("in.obj")) + " -o " +
              quote(p("lo.obj")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("face 1 in REF's order has no group"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--drop group"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("lo.obj")));
  r = run_qsp("reorder --like " + quote(p("ref.obj")) + " " + quote(p("in.obj")) + " -o " +
              quote(p("lo.qsp")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Binary doubles that are float32 values are held exactly: no refusal.
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nproperty double red\nproperty double green\nproperty double blue\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  const auto put = [&ply](auto v) { ply.append(reinterpret_cast<const char*>(&v), sizeof v); };
  for (int v = 0; v < 4; ++v) {
    put(float(v & 1)), put(float(v >> 1)), put(0.0f);
    for (int c = 0; c < 3; ++c) put(static_cast<double>(0.1f * static_cast<float>(v + c)));
  }
  put(std::uint8_t{4}), put(0), put(1), put(3), put(2);
  spit(p("d.ply"), ply);
  r = run_qsp("compress -f " + quote(p("d.ply")) + " " + quote(p("d.qsp")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  // --drop applies to a .qsp IN too, and says what it dropped.
  spit(p("c.off"), "COFF\n4 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n1 1 0 0 0 1 1\n0 1 0 1 1 1 1\n4 0 1 2 3\n");
  ASSERT_EQ(run_qsp("compress -f " + quote(p("c.off")) + " " + quote(p("c.qsp"))).exit_code, 0);
  r = run_qsp("reorder --drop color --like " + quote(p("c.off")) + " " + quote(p("c.qsp")) + " -o " +
              quote(p("c2.off")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("dropped its color"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(p("c2.off")).substr(0, 4), "OFF\n");
  // Float colours of 0 and 1 stay float in PLY.
  r = run_qsp("decompress -f " + quote(p("c.qsp")) + " -o " + quote(p("c.ply")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(slurp(p("c.ply")).find("property float red"), std::string::npos);
  // OFF's one-number face colours (colour-map indices): PLY refuses them, naming them; OFF keeps them.
  spit(p("m.off"), "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2 7\n3 0 2 3 300\n");
  ASSERT_EQ(run_qsp("compress -f " + quote(p("m.off")) + " " + quote(p("m.qsp"))).exit_code, 0);
  r = run_qsp("decompress -f " + quote(p("m.qsp")) + " -o " + quote(p("m.ply")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("colour-map indices"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("m.ply")));
  r = run_qsp("decompress -f " + quote(p("m.qsp")) + " -o " + quote(p("m2.off")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(slurp(p("m2.off")).find(" 300\n"), std::string::npos) << slurp(p("m2.off"));
}

}  // namespace
}  // namespace qsp
