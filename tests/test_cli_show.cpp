// `qsp show` and `qsp layout` end to end: the PNG decodes at the asked size and is not blank, the
// same call gives the same bytes, another partition another picture, a .qsp its stored partition;
// the SVG is XML; the layout has a face per patch over its schematic vertices in order; --patches
// tags every face and its `l` lines are exactly the schematic edges.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "qsp/canonical.h"
#include "qsp/codec.h"
#include "qsp/io.h"
#include "qsp/smaller.h"
#include "support/cli.h"
#include "support/mesh_gen.h"
#include "support/png.h"
#include "support/polygon.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::run_qsp;
using testing::slurp;

using CliShow = testing::TempDirTest;

const std::string kSpot = std::string(QSP_TESTDATA_DIR) + "/keenan_spot_quadrangulated.obj";
const std::string kMulti = std::string(QSP_TESTDATA_DIR) + "/multi_component.obj";

std::string show(const std::string& in, const std::string& out, const std::string& extra = "") {
  const auto r = run_qsp("show -f " + quote(in) + " -o " + quote(out) + " " + extra);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return slurp(out);
}

// Fraction of pixels that differ between two decoded pictures of one size.
double differing(const testing::DecodedPng& a, const testing::DecodedPng& b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.rgb.size(); i += 3)
    n += a.rgb[i] != b.rgb[i] || a.rgb[i + 1] != b.rgb[i + 1] || a.rgb[i + 2] != b.rgb[i + 2];
  return double(n) / double(a.rgb.size() / 3);
}

TEST_F(CliShow, PngDecodesAtTheAskedSizeAndIsNotBlank) {
  for (const std::string& in : {kSpot, kMulti, std::string(QSP_TESTDATA_DIR) + "/torus_twist_9x6_t2.obj"}) {
    SCOPED_TRACE(in);
    const auto d = testing::decode_png(show(in, p("a.png"), "--size 300x200 --view 20,15"));
    ASSERT_EQ(d.error, "");
    EXPECT_EQ(d.width, 300u);
    EXPECT_EQ(d.height, 200u);
    std::size_t drawn = 0, dark = 0;
    for (std::size_t i = 0; i < d.rgb.size(); i += 3) {
      drawn += d.rgb[i] != 255 || d.rgb[i + 1] != 255 || d.rgb[i + 2] != 255;
      dark += d.rgb[i] < 60 && d.rgb[i + 1] < 60 && d.rgb[i + 2] < 60;
    }
    EXPECT_GT(drawn, 300u * 200 / 30);
    if (in != kMulti && in.find("torus") == std::string::npos) {
      EXPECT_GT(dark, 100u) << "lines and dots";
    }
  }
  // The default size.
  const auto d = testing::decode_png(show(kSpot, p("b.png")));
  EXPECT_EQ(d.width, 1024u);
  EXPECT_EQ(d.height, 1024u);
}

TEST_F(CliShow, SameCallSameBytesAndAnotherPartitionAnotherPicture) {
  const std::string a = show(kSpot, p("a.png"), "--size 256x256");
  EXPECT_EQ(show(kSpot, p("b.png"), "--size 256x256"), a);
  const std::string g = show(kSpot, p("g.png"), "--size 256x256 --partition greedy");
  EXPECT_NE(g, a);
  EXPECT_GT(differing(testing::decode_png(a), testing::decode_png(g)), 0.01);
  EXPECT_NE(show(kSpot, p("grid.png"), "--size 256x256 --grid"), a);
  EXPECT_NE(show(kSpot, p("v.png"), "--size 256x256 --view 90,0"), a);
}

TEST_F(CliShow, QspInputShowsItsStoredPartition) {
  // The decoded mesh is numbered canonically, so a few pixels where faces tie in depth may differ; the
  // stored (greedy) partition's picture is that of greedy on the mesh, not motorcycle's.
  for (const char* flags : {"", "--keep-order"}) {
    SCOPED_TRACE(flags);
    const std::string q = p("spot.qsp");
    ASSERT_EQ(run_qsp("compress -f --positions-only --partition greedy " + std::string(flags) + " " +
                      quote(kSpot) + " " + quote(q))
                  .exit_code,
              0);
    const auto stored = testing::decode_png(show(q, p("q.png"), "--size 256x256"));
    const auto greedy = testing::decode_png(show(kSpot, p("g.png"), "--size 256x256 --partition greedy"));
    const auto moto = testing::decode_png(show(kSpot, p("m.png"), "--size 256x256"));
    ASSERT_EQ(stored.error, "");
    EXPECT_LT(differing(stored, greedy), 0.002);
    EXPECT_GT(differing(stored, moto), 0.01);
    // The exported layout is canonical: byte for byte the same but for its first (header) line.
    ASSERT_EQ(run_qsp("layout -f " + quote(q) + " -o " + quote(p("q.obj"))).exit_code, 0);
    ASSERT_EQ(run_qsp("layout -f --partition greedy " + quote(kSpot) + " -o " + quote(p("g.obj"))).exit_code,
              0);
    const std::string lq = slurp(p("q.obj")), lg = slurp(p("g.obj"));
    EXPECT_EQ(lq.substr(lq.find('\n')), lg.substr(lg.find('\n')));
  }
  // auto is what compress stores by default.
  ASSERT_EQ(run_qsp("compress -f --positions-only " + quote(kSpot) + " " + quote(p("auto.qsp"))).exit_code,
            0);
  ASSERT_EQ(run_qsp("layout -f " + quote(p("auto.qsp")) + " -o " + quote(p("a1.obj"))).exit_code, 0);
  ASSERT_EQ(run_qsp("layout -f --partition auto " + quote(kSpot) + " -o " + quote(p("a2.obj"))).exit_code, 0);
  const std::string a1 = slurp(p("a1.obj")), a2 = slurp(p("a2.obj"));
  EXPECT_EQ(a1.substr(a1.find('\n')), a2.substr(a2.find('\n')));
}

TEST_F(CliShow, SvgIsXml) {
  for (const std::string& in : {kSpot, kMulti}) {
    SCOPED_TRACE(in);
    const std::string svg = show(in, p("a.svg"), "--size 400x300 --grid");
    EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
    const std::string check =
        "python3 -c 'import sys, xml.etree.ElementTree as E; r = E.parse(sys.argv[1]).getroot(); "
        "sys.exit(0 if r.tag.endswith(\"svg\") and len(r.findall(\".//{*}path\")) > 10 else 1)' " +
        quote(p("a.svg"));
    EXPECT_EQ(std::system(check.c_str()), 0);
    EXPECT_EQ(show(in, p("b.svg"), "--size 400x300 --grid"), svg);
  }
}

TEST_F(CliShow, BadArgumentsFailCleanly) {
  const std::string out = p("x.png");
  EXPECT_EQ(run_qsp("show " + quote(kSpot) + " -o " + quote(out) + " --size 0x10").exit_code, 2);
  EXPECT_EQ(run_qsp("show " + quote(kSpot) + " -o " + quote(out) + " --size 10").exit_code, 2);
  // Out of range, or wrapping round to a valid size as sscanf's %u reads them (4294967297 is 2^32 + 1).
  for (const char* size : {"99999x99999", "8193x10", "4294967297x10", "10x4294967297", "-4294967295x10",
                           "+10x10", "10x 10", "10x10x"}) {
    const auto r = run_qsp("show " + quote(kSpot) + " -o " + quote(out) + " --size '" + size + "'");
    EXPECT_EQ(r.exit_code, 2) << size;
    EXPECT_NE(r.err.find("--size must be WxH"), std::string::npos) << size << ": " << r.err;
  }
  EXPECT_EQ(run_qsp("show " + quote(kSpot) + " -o " + quote(out) + " --view 10").exit_code, 2);
  EXPECT_EQ(run_qsp("show " + quote(kSpot) + " -o " + quote(p("x.jpg"))).exit_code, 2);
  EXPECT_EQ(run_qsp("show " + quote(kSpot) + " -o " + quote(out) + " --partition stored").exit_code, 2);
  EXPECT_EQ(run_qsp("show " + quote(p("missing.obj")) + " -o " + quote(out)).exit_code, 3);
  const auto bad = run_qsp("show " + std::string(QSP_TESTDATA_DIR) + "/invalid/topology/" +
                           fs::directory_iterator(fs::path(QSP_TESTDATA_DIR) / "invalid" / "topology")
                               ->path()
                               .filename()
                               .string() +
                           " -o " + quote(out));
  EXPECT_EQ(bad.exit_code, 1) << bad.err;
  EXPECT_FALSE(fs::exists(out)) << "no output on failure";
  EXPECT_EQ(run_qsp("layout " + quote(kSpot)).exit_code, 2) << "needs an output";
  EXPECT_EQ(run_qsp("layout " + quote(kSpot) + " -o " + quote(p("x.ply"))).exit_code, 2);
}

TEST_F(CliShow, SvgRefusesBeyondItsFaceLimit) {
  const std::string in = p("grid.obj"), out = p("grid.svg");
  write_file_atomic(in, write_obj(testing::grid(320, 320)), true);  // 102400 faces
  const auto r = run_qsp("show " + quote(in) + " -o " + quote(out));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("at most 100000 faces"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(".png"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(run_qsp("show " + quote(in) + " -o " + quote(p("grid.png")) + " --size 64x64").exit_code, 0);
}

// Mesh faces as sorted vertex lists, for comparing face sets across files.
std::multiset<std::vector<std::uint32_t>> face_set(const QuadMesh& m) {
  std::multiset<std::vector<std::uint32_t>> out;
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    std::vector<std::uint32_t> q(m.quads.begin() + 4 * f, m.quads.begin() + 4 * f + 4);
    std::sort(q.begin(), q.end());
    out.insert(q);
  }
  return out;
}

// Per group: whether it is a whole annulus or torus component, with no extraordinary vertex and no
// boundary corner (those components have no schematic edges).
std::vector<std::uint8_t> closed_groups(const Adjacency& adj, const std::vector<std::uint32_t>& face_group,
                                        std::size_t groups) {
  std::vector<std::uint8_t> closed(groups, 1);
  for (std::uint32_t k = 0; k < face_group.size(); ++k)
    for (std::uint32_t c = 0; c < 4; ++c) {
      const std::uint32_t v = adj.origin[4 * k + c];
      if (adj.extraordinary(v) || (adj.boundary[v] && adj.valence[v] == 2)) closed[face_group[k]] = 0;
    }
  return closed;
}

std::vector<std::uint32_t> indices(std::istringstream& ls) {
  std::vector<std::uint32_t> out;
  for (long v; ls >> v;) out.push_back(static_cast<std::uint32_t>(v - 1));
  return out;
}

// Calls f(keyword, the rest of the line as a stream, the line) for each line of OBJ text.
template <class F>
void each_statement(const std::string& text, F f) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    f(kw, ls, line);
  }
}

// A --patches OBJ as written: vertices (with their text), faces with the group they are in, lines.
struct PatchesObj {
  QuadMesh mesh;
  std::vector<std::string> position;              // per vertex: its coordinates as written
  std::vector<std::string> groups;                // group names in file order
  std::vector<std::uint32_t> face_group;          // per face: its group (index into groups)
  std::vector<std::vector<std::uint32_t>> lines;  // `l` polylines, 0-based vertices
  std::size_t faces_before_any_group = 0;
};

PatchesObj read_patches_obj(const std::string& text) {
  PatchesObj out;
  each_statement(text, [&](const std::string& kw, std::istringstream& ls, const std::string& line) {
    if (kw == "v") {
      out.position.push_back(line.substr(2));
      float x, y, z;
      ls >> x >> y >> z;
      out.mesh.positions.insert(out.mesh.positions.end(), {x, y, z});
    } else if (kw == "g") {
      std::string name;
      ls >> name;
      out.groups.push_back(name);
    } else if (kw == "f") {
      out.faces_before_any_group += out.groups.empty();
      for (std::uint32_t i : indices(ls)) out.mesh.quads.push_back(i);
      out.face_group.push_back(static_cast<std::uint32_t>(out.groups.size() - 1));
    } else if (kw == "l") {
      out.lines.push_back(indices(ls));
    }
  });
  return out;
}

TEST_F(CliShow, LayoutHasAFacePerPatchOverItsSchematicVertices) {
  for (const std::string& in : {kSpot, kMulti, std::string(QSP_TESTDATA_DIR) + "/l_shape.obj",
                                std::string(QSP_TESTDATA_DIR) + "/mh_fedora.obj"}) {
    for (PartitionMode mode : {PartitionMode::kMotorcycle, PartitionMode::kGreedy, PartitionMode::kMerge}) {
      SCOPED_TRACE(in + " " + partition_mode_name(mode));
      const auto r = run_qsp("layout -f " + quote(in) + " -o " + quote(p("l.obj")) + " --partition " +
                             partition_mode_name(mode));
      ASSERT_EQ(r.exit_code, 0) << r.err;
      const QuadMesh m = read_mesh_file(in);
      const Adjacency adj = build_adjacency(m);
      const CanonicalMesh cm = canonicalize(m, adj, partition(adj, mode, m.positions));
      // Expected: per patch the positions of the schematic vertices around it.
      std::vector<std::vector<std::array<float, 3>>> want;
      for (const auto& c : cm.components) {
        if (c.part.kind == ComponentKind::kAnnulus || c.part.kind == ComponentKind::kTorus) continue;
        const Schematic& s = c.part.schematic;
        for (std::uint32_t f = 0; f < s.face_count(); ++f) {
          if (s.face_hole[f]) continue;
          std::vector<std::array<float, 3>> ring;
          std::uint32_t d = s.face_dart[f];
          do {
            const std::uint32_t v = c.map.vertex[s.dart_vertex[d]];
            ring.push_back({m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]});
            d = s.dart_next[d];
          } while (d != s.face_dart[f]);
          want.push_back(ring);
        }
      }
      std::vector<std::array<float, 3>> v;
      std::vector<std::vector<std::array<float, 3>>> got;
      each_statement(slurp(p("l.obj")),
                     [&](const std::string& kw, std::istringstream& ls, const std::string&) {
                       if (kw == "v") {
                         std::array<float, 3> p{};
                         ls >> p[0] >> p[1] >> p[2];
                         v.push_back(p);
                       } else if (kw == "f") {
                         std::vector<std::array<float, 3>> ring;
                         for (std::uint32_t i : indices(ls)) ring.push_back(v.at(i));
                         got.push_back(ring);
                       }
                     });
      EXPECT_EQ(got.size(), partition_size(partition(adj, mode, m.positions)).patches -
                                std::count_if(cm.components.begin(), cm.components.end(), [](const auto& c) {
                                  return c.part.kind == ComponentKind::kAnnulus ||
                                         c.part.kind == ComponentKind::kTorus;
                                }));
      EXPECT_EQ(got, want);
    }
  }
}

// The layout read against the --patches file only (not qsp's schematic): walking a layout face, each
// step from one of its vertices to the next is one `l` polyline, with the patch's own faces on its left
// (the mesh's orientation) and as many mesh edges as the face's comment says; every side of every line
// that has a face is walked exactly once. So no T-junction is left out, the corners are in order, and
// the lengths are the sides'.
TEST_F(CliShow, LayoutFacesWalkTheLinesAroundTheirPatch) {
  for (const std::string& in : {kSpot, kMulti, std::string(QSP_TESTDATA_DIR) + "/l_shape.obj",
                                std::string(QSP_TESTDATA_DIR) + "/mh_fedora.obj",
                                std::string(QSP_TESTDATA_DIR) + "/annulus_12x3.obj"}) {
    for (const char* mode : {"motorcycle", "greedy", "merge"}) {
      SCOPED_TRACE(in + " " + mode);
      const auto r = run_qsp("layout -f " + quote(in) + " -o " + quote(p("l.obj")) + " --patches " +
                             quote(p("p.obj")) + " --partition " + mode);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      const PatchesObj po = read_patches_obj(slurp(p("p.obj")));
      const QuadMesh& mesh = po.mesh;
      const auto& lines = po.lines;
      ASSERT_EQ(po.faces_before_any_group, 0u);
      for (std::size_t g = 0; g < po.groups.size(); ++g)
        ASSERT_EQ(po.groups[g], "patch_" + std::to_string(g));
      const std::vector<std::uint32_t>& face_group = po.face_group;
      const std::vector<std::string>& position = po.position;
      ASSERT_EQ(face_group.size(), mesh.face_count());
      const Adjacency adj = build_adjacency(mesh);
      std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> halfedge;
      for (std::uint32_t h = 0; h < adj.halfedge_count(); ++h) halfedge[{adj.origin[h], adj.dest(h)}] = h;
      std::map<std::string, std::uint32_t> vertex_at;
      for (std::uint32_t v = 0; v < position.size(); ++v)
        ASSERT_TRUE(vertex_at.emplace(position[v], v).second) << "two vertices at " << position[v];
      // Each side of each line: from its first vertex to its last (face on the left of the first edge).
      struct Side {
        std::uint32_t from, to, patch, length;
        bool walked;
      };
      std::vector<Side> sides;
      for (const auto& l : lines) {
        ASSERT_GE(l.size(), 2u);
        for (int dir = 0; dir < 2; ++dir) {
          const std::uint32_t a = dir ? l.back() : l.front(), b = dir ? l[l.size() - 2] : l[1];
          ASSERT_TRUE(halfedge.count({a, b})) << "a line off the mesh edges";
          const std::uint32_t h = halfedge.at({a, b});
          if (adj.is_exterior(h)) continue;
          sides.push_back({a, dir ? l.front() : l.back(), face_group[adj.face(h)],
                           static_cast<std::uint32_t>(l.size() - 1), false});
        }
      }
      // The layout: walk each face.
      std::vector<std::uint32_t> layout_vertex;
      std::uint32_t patch = ~0u;
      std::vector<std::uint32_t> lengths;
      std::size_t faces = 0;
      each_statement(
          slurp(p("l.obj")), [&](const std::string& kw, std::istringstream& ls, const std::string& line) {
            if (line.rfind("# patch ", 0) == 0) {
              patch = static_cast<std::uint32_t>(std::stoul(line.substr(8)));
              lengths.clear();
              const std::size_t at = line.find("edge lengths");
              if (at != std::string::npos) {
                std::istringstream numbers(line.substr(at + 12));
                for (std::uint32_t n; numbers >> n;) lengths.push_back(n);
              }
            } else if (kw == "v") {
              ASSERT_TRUE(vertex_at.count(line.substr(2))) << "a layout vertex off the mesh: " << line;
              layout_vertex.push_back(vertex_at.at(line.substr(2)));
            } else if (kw == "f") {
              ++faces;
              std::vector<std::uint32_t> ring;
              for (std::uint32_t i : indices(ls)) ring.push_back(layout_vertex.at(i));
              ASSERT_EQ(ring.size(), lengths.size()) << line;
              for (std::size_t k = 0; k < ring.size(); ++k) {
                const std::uint32_t u = ring[k], v = ring[(k + 1) % ring.size()];
                auto it = std::find_if(sides.begin(), sides.end(), [&](const Side& s) {
                  return !s.walked && s.from == u && s.to == v && s.patch == patch && s.length == lengths[k];
                });
                ASSERT_NE(it, sides.end()) << "patch " << patch << ": no line " << u << " -> " << v
                                           << " of length " << lengths[k] << " with the patch on its left";
                it->walked = true;
              }
            }
          });
      EXPECT_EQ(faces == 0, lines.empty()) << "an annulus alone has neither";
      for (const Side& s : sides)
        EXPECT_TRUE(s.walked) << "line " << s.from << " -> " << s.to << " of patch " << s.patch;
    }
  }
}

TEST_F(CliShow, PatchesTagEveryFaceAndLinesAreTheSchematicEdges) {
  for (const std::string& in : {kSpot, kMulti, std::string(QSP_TESTDATA_DIR) + "/mh_fedora.obj"}) {
    for (const char* mode : {"motorcycle", "greedy", "merge", "auto"}) {
      SCOPED_TRACE(in + " " + mode);
      const auto r =
          run_qsp("layout -f " + quote(in) + " --patches " + quote(p("p.obj")) + " --partition " + mode);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      ASSERT_EQ(run_qsp("layout -f " + quote(in) + " --patches " + quote(p("p.ply")) + " --partition " + mode)
                    .exit_code,
                0);
      const QuadMesh m = read_mesh_file(in);
      const Adjacency adj0 = build_adjacency(m);
      std::uint64_t patches = 0, edges = 0;
      if (mode == std::string("auto")) {
        for (const TopologyCode& code : file_topology(encode(m)).codes) {
          const ComponentPartition part = partition_from_code(code);
          const bool closed = part.kind == ComponentKind::kAnnulus || part.kind == ComponentKind::kTorus;
          patches += closed ? 1 : part.schematic.patch_count();
          edges += closed ? 0 : part.schematic.edge_count();
        }
      } else {
        PartitionMode pm = PartitionMode::kMotorcycle;
        ASSERT_TRUE(parse_partition_mode(mode, pm));
        const PartitionSize size = partition_size(partition(adj0, pm, m.positions));
        patches = size.patches, edges = size.edges;
      }
      const PatchesObj po = read_patches_obj(slurp(p("p.obj")));
      const QuadMesh& back = po.mesh;
      const std::vector<std::uint32_t>& face_group = po.face_group;
      const std::vector<std::string>& groups = po.groups;
      EXPECT_EQ(po.faces_before_any_group, 0u) << "a face before any group";
      std::set<std::pair<std::uint32_t, std::uint32_t>> line_edges;
      std::size_t line_edge_count = 0;
      for (const auto& path : po.lines) {
        ASSERT_GE(path.size(), 2u);
        for (std::size_t k = 0; k + 1 < path.size(); ++k, ++line_edge_count)
          line_edges.insert(std::minmax(path[k], path[k + 1]));
      }
      EXPECT_EQ(back.positions, m.positions);
      EXPECT_EQ(face_set(back), face_set(m)) << "every face exactly once";
      ASSERT_EQ(groups.size(), patches);
      for (std::size_t g = 0; g < groups.size(); ++g) EXPECT_EQ(groups[g], "patch_" + std::to_string(g));
      // Schematic edges: every mesh edge where two patches meet and the mesh boundary (annulus and
      // torus components aside), each mesh edge in one line; cut along them, the mesh falls into
      // exactly these patches again.
      const Adjacency adj = build_adjacency(back);
      const std::vector<std::uint8_t> group_closed = closed_groups(adj, face_group, groups.size());
      std::vector<std::uint32_t> cuts;
      for (std::uint32_t h = 0; h < adj.halfedge_count(); ++h) {
        const std::uint32_t t = adj.twin[h];
        const bool on_line = line_edges.count(std::minmax(adj.origin[h], adj.origin[t])) != 0;
        const std::uint32_t f = adj.face(adj.is_exterior(h) ? t : h);
        const bool closed = group_closed[face_group[f]] != 0;
        if (!closed && (adj.is_exterior(h) || adj.is_exterior(t) ||
                        face_group[adj.face(h)] != face_group[adj.face(t)])) {
          EXPECT_TRUE(on_line) << "edge " << adj.origin[h] << "-" << adj.origin[t];
        }
        if (on_line && h < t) cuts.push_back(h);
      }
      EXPECT_EQ(line_edge_count, line_edges.size()) << "a mesh edge in two lines";
      EXPECT_EQ(cuts.size(), line_edges.size()) << "every line runs along mesh edges";
      const PartitionSize size = partition_size(partition_from_cuts(adj, cuts));
      EXPECT_EQ(size.patches, patches);
      EXPECT_EQ(size.edges, edges);
      // PLY: the same faces, each with its group's patch number.
      const std::string ply = slurp(p("p.ply"));
      ASSERT_NE(ply.find("property int patch"), std::string::npos);
      std::istringstream pt(ply.substr(ply.find("end_header\n") + 11));
      for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        float x, y, z;
        pt >> x >> y >> z;
      }
      std::map<std::vector<std::uint32_t>, std::uint32_t> ply_patch, ply_colour;
      for (std::size_t f = 0; f < m.face_count(); ++f) {
        int n = 0;
        std::vector<std::uint32_t> q(4);
        unsigned patch = 0, red = 0, green = 0, blue = 0;
        pt >> n >> q[0] >> q[1] >> q[2] >> q[3] >> patch >> red >> green >> blue;
        ASSERT_EQ(n, 4);
        std::sort(q.begin(), q.end());
        ply_patch[q] = patch;
        ply_colour[q] = red << 16 | green << 8 | blue;
      }
      // Each face its group's patch number; one colour per patch, and patches that share an edge differ.
      std::vector<std::uint32_t> colour(back.face_count());
      std::map<std::uint32_t, std::uint32_t> patch_colour;
      for (std::size_t f = 0; f < back.face_count(); ++f) {
        std::vector<std::uint32_t> q(back.quads.begin() + 4 * f, back.quads.begin() + 4 * f + 4);
        std::sort(q.begin(), q.end());
        EXPECT_EQ(ply_patch[q], face_group[f]);
        colour[f] = ply_colour[q];
        EXPECT_EQ(patch_colour.emplace(face_group[f], colour[f]).first->second, colour[f])
            << "patch " << face_group[f];
      }
      for (std::uint32_t h = 0; h < 4 * adj.face_count; ++h) {
        const std::uint32_t t = adj.twin[h];
        if (adj.is_exterior(t) || face_group[adj.face(h)] == face_group[adj.face(t)]) continue;
        EXPECT_NE(colour[adj.face(h)], colour[adj.face(t)])
            << "patches " << face_group[adj.face(h)] << " and " << face_group[adj.face(t)];
      }
    }
  }
}

// A polygon mesh (triangles, n-gons; qsp/submesh.h): show draws it with its non-quads grey, layout
// exports its quad submesh's partition, and --patches holds every face of the file as it was, the
// quads in patch groups and the rest in `non_quads`, read back here by a parser of our own.
TEST_F(CliShow, PolygonMeshesAreDrawnAndExported) {
  testing::Grid g = testing::Grid::make(5, 4, [](int i, int j) {
    return i == 1 && j == 1 ? 't' : i == 3 && j == 2 ? '.' : 'q';
  });
  {
    std::ofstream out(p("poly.obj"));
    for (int y = 0; y <= 4; ++y)
      for (int x = 0; x <= 5; ++x) out << "v " << x << ' ' << y << " 0\n";
    for (std::uint32_t f = 0; f < g.p.face_count(); ++f) {
      out << 'f';
      for (std::uint32_t k = g.p.offsets[f]; k < g.p.offsets[f + 1]; ++k) out << ' ' << g.p.corners[k] + 1;
      out << '\n';
    }
    out << "f " << g.id(3, 2) + 1 << ' ' << g.id(4, 2) + 1 << ' ' << g.id(4, 3) + 1 << ' ' << g.id(3, 3) + 1
        << "\n";  // the hole closed again, as a quad of its own (orientation kept)
  }
  std::vector<std::string> inputs = {p("poly.obj")};
  for (const char* name : {"pmp_suzanne.obj", "osd_catmark_bishop.obj"})
    if (fs::exists(fs::path(QSP_SHARED_DIR) / "meshes" / name))
      inputs.push_back((fs::path(QSP_SHARED_DIR) / "meshes" / name).string());
  for (const std::string& in : inputs) {
    SCOPED_TRACE(in);
    const testing::Poly want = testing::read_faces(in);
    std::size_t non_quads = 0;
    for (std::uint32_t f = 0; f < want.face_count(); ++f) non_quads += want.degree(f) != 4;
    ASSERT_GT(non_quads, 0u);
    const auto d = testing::decode_png(show(in, p("a.png"), "--size 200x200 --view 20,15"));
    ASSERT_EQ(d.error, "");
    std::size_t grey = 0;
    for (std::size_t i = 0; i < d.rgb.size(); i += 3)
      grey += d.rgb[i] == d.rgb[i + 1] && d.rgb[i] == d.rgb[i + 2] && d.rgb[i] > 60 && d.rgb[i] < 200;
    EXPECT_GT(grey, 30u) << "the non-quads are drawn grey";
    EXPECT_NE(show(in, p("a.svg")).find("</svg>"), std::string::npos);

    const auto r =
        run_qsp("layout -f " + quote(in) + " -o " + quote(p("l.obj")) + " --patches " + quote(p("p.obj")));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::string group;
    std::vector<std::vector<std::uint32_t>> faces, lines;
    std::size_t vertices = 0, in_non_quads = 0;
    each_statement(slurp(p("p.obj")), [&](const std::string& kw, std::istringstream& ls, const std::string&) {
      if (kw == "v") ++vertices;
      if (kw == "g") ls >> group;
      if (kw == "l") lines.push_back(indices(ls));
      if (kw != "f") return;
      faces.push_back(indices(ls));
      if (group == "non_quads") {
        ++in_non_quads;
        EXPECT_NE(faces.back().size(), 4u) << "a quad outside the patches";
      } else {
        EXPECT_EQ(group.rfind("patch_", 0), 0u) << group;
        EXPECT_EQ(faces.back().size(), 4u) << "a non-quad in " << group;
      }
    });
    EXPECT_EQ(vertices, want.nv);
    EXPECT_EQ(in_non_quads, non_quads);
    // The same faces, each with its corners in the file's order (the groups reorder faces only).
    std::multiset<std::vector<std::uint32_t>> a(faces.begin(), faces.end()), b;
    for (std::uint32_t f = 0; f < want.face_count(); ++f)
      b.insert(std::vector<std::uint32_t>(want.corners.begin() + want.offsets[f],
                                          want.corners.begin() + want.offsets[f + 1]));
    EXPECT_TRUE(a == b) << "--patches holds other faces than the file";
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (const auto& f : faces)
      for (std::size_t k = 0; k < f.size(); ++k) edges.insert(std::minmax(f[k], f[(k + 1) % f.size()]));
    EXPECT_FALSE(lines.empty());
    for (const auto& l : lines)
      for (std::size_t k = 0; k + 1 < l.size(); ++k)
        EXPECT_TRUE(edges.count(std::minmax(l[k], l[k + 1]))) << "an l step that is no mesh edge";

    // The PLY export: patch -1 exactly on the non-quads.
    ASSERT_EQ(run_qsp("layout -f " + quote(in) + " --patches " + quote(p("p.ply"))).exit_code, 0);
    std::istringstream ply(slurp(p("p.ply")));
    std::size_t minus_one = 0, face_lines = 0;
    bool body = false;
    std::size_t skip = want.nv;
    for (std::string line; std::getline(ply, line);) {
      if (!body) {
        body = line == "end_header";
        continue;
      }
      if (skip) {
        --skip;
        continue;
      }
      std::istringstream ls(line);
      std::uint32_t n = 0, v = 0;
      long patch = 0;
      ls >> n;
      for (std::uint32_t k = 0; k < n; ++k) ls >> v;
      ls >> patch;
      ++face_lines;
      minus_one += patch == -1;
      EXPECT_EQ(patch == -1, n != 4);
    }
    EXPECT_EQ(face_lines, want.face_count());
    EXPECT_EQ(minus_one, non_quads);
  }
  // A polygon .qsp: drawn as its decoded mesh; its stored partition is not read yet, and says so.
  ASSERT_EQ(run_qsp("compress -f " + quote(p("poly.obj")) + " " + quote(p("poly.qsp"))).exit_code, 0);
  EXPECT_FALSE(show(p("poly.qsp"), p("q.png")).empty());
  const auto stored =
      run_qsp("show -f " + quote(p("poly.qsp")) + " -o " + quote(p("q.png")) + " --partition stored");
  EXPECT_EQ(stored.exit_code, 2);
  EXPECT_NE(stored.err.find("polygon mesh"), std::string::npos) << stored.err;
}

}  // namespace
}  // namespace qsp
