// The drawing stage (qsp/render.h) and the partition view it draws (qsp/layout_export.h), over every
// corpus mesh: the PNG decodes to the image, the view covers every face and every schematic edge,
// neighbouring patches get different colours, and numbering does not change the view.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "qsp/canonical.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/layout_export.h"
#include "qsp/render.h"
#include "qsp/smaller.h"
#include "support/corpus.h"
#include "support/mesh_gen.h"
#include "support/png.h"
#include "support/polygon.h"

namespace qsp {
namespace {

PatchView view_of(const QuadMesh& m, const Adjacency& adj, PartitionMode mode) {
  return view_partition(adj, canonicalize(m, adj, partition(adj, mode, m.positions)));
}

// Per patch of the view: 1 if it is a whole annulus or torus component (no schematic edges there).
std::vector<std::uint8_t> closed_patches(const CanonicalMesh& cm) {
  std::vector<std::uint8_t> out;
  for (const CanonicalComponent& c : cm.components) {
    if (c.part.kind == ComponentKind::kAnnulus || c.part.kind == ComponentKind::kTorus)
      out.push_back(1);
    else
      out.resize(out.size() + c.part.schematic.patch_count(), 0);
  }
  return out;
}

// The patch on each side of every mesh edge: the schematic edges hold every edge where two patches
// meet and the mesh boundary (and may run through a patch that borders itself); cutting along them
// gives back the same patches.
void check_view(const QuadMesh& m, const Adjacency& adj, PartitionMode mode) {
  const CanonicalMesh cm = canonicalize(m, adj, partition(adj, mode, m.positions));
  const PatchView v = view_partition(adj, cm);
  const std::vector<std::uint8_t> closed = closed_patches(cm);
  ASSERT_EQ(closed.size(), v.patch_count);
  ASSERT_EQ(v.face_patch.size(), m.face_count());
  for (std::uint32_t p : v.face_patch) ASSERT_LT(p, v.patch_count);
  std::set<std::pair<std::uint32_t, std::uint32_t>> path_edges;
  for (std::uint32_t e = 0; e < v.edge_count(); ++e) {
    ASSERT_GE(v.edge_first[e + 1] - v.edge_first[e], 2u);
    for (std::uint32_t k = v.edge_first[e]; k + 1 < v.edge_first[e + 1]; ++k)
      EXPECT_TRUE(path_edges.insert(std::minmax(v.edge_path[k], v.edge_path[k + 1])).second)
          << "a mesh edge on two schematic edges";
  }
  std::vector<std::uint32_t> cuts;
  for (std::uint32_t h = 0; h < adj.halfedge_count(); ++h) {
    const std::uint32_t t = adj.twin[h];
    const bool boundary = adj.is_exterior(h) || adj.is_exterior(t);
    if (closed[v.face_patch[adj.face(adj.is_exterior(h) ? t : h)]]) continue;
    const bool on_path = path_edges.count(std::minmax(adj.origin[h], adj.origin[t])) != 0;
    if (boundary || v.face_patch[adj.face(h)] != v.face_patch[adj.face(t)]) {
      EXPECT_TRUE(on_path);
    }
    if (on_path && h < t) cuts.push_back(h);
  }
  const PartitionSize size = partition_size(partition_from_cuts(adj, cuts));
  EXPECT_EQ(size.patches, v.patch_count);
  EXPECT_EQ(size.edges, v.edge_count());
  // Neighbours differ in colour (no corpus patch has kPatchPaletteSize or more neighbours).
  for (std::uint32_t h = 0; h < 4 * adj.face_count; ++h) {
    const std::uint32_t t = adj.twin[h];
    if (adj.is_exterior(t)) continue;
    const std::uint32_t p = v.face_patch[adj.face(h)], q = v.face_patch[adj.face(t)];
    if (p != q) {
      EXPECT_NE(v.patch_colour[p], v.patch_colour[q]) << "patches " << p << " and " << q;
    }
  }
  for (std::uint32_t x : v.extraordinary) EXPECT_TRUE(adj.extraordinary(x));
  for (std::uint32_t x : v.t_junctions) EXPECT_EQ(adj.deficiency(x), 0);
}

TEST(Render, ViewAndPngOnEveryCorpusMesh) {
  RenderOptions o;
  o.width = 96;
  o.height = 64;
  o.azimuth = 30;
  o.elevation = 20;
  for (const auto& path : testing::corpus()) {
    SCOPED_TRACE(path.string());
    QuadMesh m;
    Adjacency adj;
    if (!testing::read_valid(path, m, &adj)) continue;
    for (PartitionMode mode : {PartitionMode::kMotorcycle, PartitionMode::kGreedy, PartitionMode::kMerge}) {
      SCOPED_TRACE(partition_mode_name(mode));
      check_view(m, adj, mode);
    }
    const PatchView v = view_of(m, adj, PartitionMode::kMotorcycle);
    const Image img = render_image(polygon_mesh(m), v, o);
    ASSERT_EQ(img.rgb.size(), 3u * 96 * 64);
    const std::string png = encode_png(img);
    const testing::DecodedPng d = testing::decode_png(png);
    ASSERT_EQ(d.error, "");
    EXPECT_EQ(d.width, 96u);
    EXPECT_EQ(d.height, 64u);
    EXPECT_TRUE(d.rgb == img.rgb);
    // Not blank: the mesh covers a good part of the picture, and more than one colour shows.
    std::size_t drawn = 0;
    std::set<std::uint32_t> colours;
    for (std::size_t i = 0; i < d.rgb.size(); i += 3) {
      drawn += d.rgb[i] != 255 || d.rgb[i + 1] != 255 || d.rgb[i + 2] != 255;
      colours.insert(d.rgb[i] << 16 | d.rgb[i + 1] << 8 | d.rgb[i + 2]);
    }
    EXPECT_GT(drawn, 96u * 64 / 20);
    EXPECT_GT(colours.size(), 4u);
    EXPECT_EQ(encode_png(render_image(polygon_mesh(m), v, o)), png) << "the same input gives the same bytes";
  }
}

TEST(Render, RenumberingGivesTheSameView) {
  // Patches are numbered canonically, so a shuffled copy gets the same colours at the same places.
  const QuadMesh m = read_mesh_file(std::string(QSP_TESTDATA_DIR) + "/keenan_spot_quadrangulated.obj");
  std::vector<std::uint32_t> old_of;
  const QuadMesh s = testing::shuffled(m, 7, &old_of);
  const Adjacency am = build_adjacency(m), as = build_adjacency(s);
  const PatchView vm = view_of(m, am, PartitionMode::kGreedy), vs = view_of(s, as, PartitionMode::kGreedy);
  ASSERT_EQ(vm.patch_count, vs.patch_count);
  EXPECT_EQ(vm.patch_colour, vs.patch_colour);
  std::vector<std::uint32_t> ext;
  for (std::uint32_t x : vs.extraordinary) ext.push_back(old_of[x]);
  EXPECT_EQ(ext, vm.extraordinary);
  std::vector<std::uint32_t> path;
  for (std::uint32_t x : vs.edge_path) path.push_back(old_of[x]);
  EXPECT_EQ(path, vm.edge_path);
}

TEST(Render, SizesAndFaceLimitAreChecked) {
  const QuadMesh m = testing::grid(4, 3);
  const Adjacency adj = build_adjacency(m);
  const PatchView v = view_of(m, adj, PartitionMode::kMotorcycle);
  RenderOptions o;
  o.width = 0;
  EXPECT_THROW(render_image(polygon_mesh(m), v, o), Error);
  o.width = kMaxRenderSide + 1;
  EXPECT_THROW(render_svg(polygon_mesh(m), v, o), Error);
  const QuadMesh big = testing::grid(320, 320);  // 102400 faces
  const Adjacency big_adj = build_adjacency(big);
  try {
    render_svg(polygon_mesh(big), view_of(big, big_adj, PartitionMode::kMotorcycle), {});
    ADD_FAILURE() << "SVG of 102400 faces";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kLimit);
    EXPECT_NE(std::string(e.what()).find("png"), std::string::npos) << e.what();
  }
}

// A polygon mesh's view (polygon_view): every quad in a patch, every other face in none; its paths and
// marks on the mesh's own vertices along its own edges; drawn with the non-quads grey.
TEST(Render, PolygonMeshesShowTheirNonQuadsGrey) {
  const testing::Grid g = testing::Grid::make(6, 5, [](int i, int j) {
    return i == 2 && j == 2 ? 't' : i == 4 && j == 1 ? '.' : 'q';
  });
  std::vector<testing::PolyCase> cases = testing::hand_polygon_cases();
  cases.insert(cases.begin(), {"grid_with_a_triangle_pair", g.p});
  for (std::uint32_t x = 0; x <= 6; ++x)  // the first case drawn flat, the others on a sphere-ish cloud
    for (std::uint32_t y = 0; y <= 5; ++y)
      for (float c : {static_cast<float>(x), static_cast<float>(y), 0.0f}) cases[0].p.positions.push_back(c);
  int grey_seen = 0;
  for (testing::PolyCase& c : cases) {
    SCOPED_TRACE(c.name);
    if (!testing::cuttable(c.p)) continue;
    if (c.p.positions.empty())
      for (std::uint32_t v = 0; v < c.p.nv; ++v)
        for (int k = 0; k < 3; ++k) c.p.positions.push_back(std::cos(static_cast<float>(v * 3 + k) * 1.7f));
    PolygonMesh m;
    m.positions = c.p.positions;
    m.face_offsets = c.p.offsets;
    m.corners = c.p.corners;
    const QuadSubmesh sub = quad_submesh(m.face_offsets, m.corners, c.p.nv, m.positions);
    const PatchView qv = view_of(sub.mesh, sub.adjacency, PartitionMode::kMotorcycle);
    const PatchView v = polygon_view(sub, qv, m.face_count());
    ASSERT_EQ(v.face_patch.size(), m.face_count());
    std::vector<std::uint32_t> faces_in(v.patch_count, 0);
    for (std::uint32_t f = 0; f < m.face_count(); ++f) {
      EXPECT_EQ(v.face_patch[f] == kInvalid, m.degree(f) != 4) << "face " << f;
      if (v.face_patch[f] != kInvalid) ++faces_in[v.face_patch[f]];
    }
    for (std::uint32_t p = 0; p < v.patch_count; ++p) EXPECT_GT(faces_in[p], 0u) << "patch " << p;
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (std::uint32_t f = 0; f < m.face_count(); ++f)
      for (std::uint32_t k = m.face_offsets[f]; k < m.face_offsets[f + 1]; ++k) {
        const std::uint32_t a = m.corners[k],
                            b = m.corners[k + 1 < m.face_offsets[f + 1] ? k + 1 : m.face_offsets[f]];
        edges.insert({std::min(a, b), std::max(a, b)});
      }
    for (std::uint32_t e = 0; e < v.edge_count(); ++e)
      for (std::uint32_t k = v.edge_first[e]; k + 1 < v.edge_first[e + 1]; ++k) {
        const std::uint32_t a = v.edge_path[k], b = v.edge_path[k + 1];
        EXPECT_TRUE(edges.count({std::min(a, b), std::max(a, b)})) << "path step " << a << "-" << b;
      }
    for (std::uint32_t x : v.extraordinary) EXPECT_LT(x, c.p.nv);
    for (std::uint32_t x : v.t_junctions) EXPECT_LT(x, c.p.nv);
    RenderOptions o;
    o.width = o.height = 128;
    const Image img = render_image(m, v, o);
    std::size_t grey_pixels = 0;  // a shaded kNonQuadColour: the three channels equal, between dark and white
    for (std::size_t i = 0; i + 2 < img.rgb.size(); i += 3)
      grey_pixels +=
          img.rgb[i] == img.rgb[i + 1] && img.rgb[i] == img.rgb[i + 2] && img.rgb[i] > 60 && img.rgb[i] < 200;
    const bool grey = grey_pixels > 100;  // more than the anti-aliased rims of a few dots
    grey_seen += grey;
    if (c.name == "grid_with_a_triangle_pair") {
      EXPECT_TRUE(grey) << "the triangle pair is drawn grey";
    }
    const std::string svg = render_svg(m, v, o);
    std::size_t paths = 0;
    for (std::size_t at = svg.find("<path d="); at != std::string::npos; at = svg.find("<path d=", at + 1))
      ++paths;
    EXPECT_EQ(paths, m.face_count()) << "one path per face";
  }
  EXPECT_GT(grey_seen, 2);
}

}  // namespace
}  // namespace qsp
