// Polygon meshes for tests: plain arrays (faces of any degree), grids to carve cases from, a reader of
// faces of any degree (qsp's OBJ reader refuses non-quads), renumbered copies, and the hand-made cases
// of tests/test_submesh.cpp by name.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "files.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/polymesh.h"
#include "qsp/submesh.h"

namespace qsp::testing {

// An OBJ file as qsp's exact reader gives it, as a PolygonMesh: positions (float64 too where float32
// does not hold them), faces as read, and the texture coordinates (every corner naming one or kInvalid),
// normals, face labels, tags and lines kept as text when the file has any.
// Without the file's statement order (test_statements.cpp tests that on its own): a keep-order file of
// these is the same bytes as before it was kept.
inline PolygonMesh read_obj_polygons(const std::filesystem::path& path) {
  PolygonMesh m =
      to_polygon_mesh(read_obj_mesh(slurp(path), path.string()), kPolygonMeshCategories | kCategoryExtra);
  m.statements.clear();
  return m;
}

// A polygon mesh as the plain arrays the API takes.
struct Poly {
  std::vector<std::uint32_t> offsets{0}, corners;
  std::uint32_t nv = 0;
  std::vector<float> positions;

  void face(std::initializer_list<std::uint32_t> vs) {
    corners.insert(corners.end(), vs.begin(), vs.end());
    offsets.push_back(static_cast<std::uint32_t>(corners.size()));
  }
  std::uint32_t face_count() const { return static_cast<std::uint32_t>(offsets.size() - 1); }
  std::uint32_t degree(std::uint32_t f) const { return offsets[f + 1] - offsets[f]; }
};

// `p` as the API's PolygonMesh. Where `p` has no positions, vertex v is put at (spacing * v, 0, 0): apart
// on a line (spacing 1) where distances choose among isomorphisms, all at the origin (spacing 0) where
// bytes must not depend on which of tied vertices comes first.
inline PolygonMesh to_mesh(const Poly& p, float spacing) {
  PolygonMesh m;
  m.face_offsets = p.offsets;
  m.corners = p.corners;
  m.positions = p.positions;
  if (m.positions.empty()) {
    m.positions.assign(3 * std::size_t{p.nv}, 0.0f);
    for (std::uint32_t v = 0; v < p.nv; ++v)
      m.positions[3 * std::size_t{v}] = spacing * static_cast<float>(v);
  }
  return m;
}

// A (w x h)-cell grid; vertex (x, y) is y * (w + 1) + x. cell() adds cell (i, j) = [i,i+1]x[j,j+1] as a
// counter-clockwise quad; split() adds it as two triangles along the diagonal (i+1,j)-(i,j+1).
struct Grid {
  int w, h;
  Poly p;
  Grid(int w_, int h_) : w(w_), h(h_) { p.nv = static_cast<std::uint32_t>((w + 1) * (h + 1)); }
  std::uint32_t id(int x, int y) const { return static_cast<std::uint32_t>(y * (w + 1) + x); }
  void cell(int i, int j) { p.face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)}); }
  void split(int i, int j) {
    p.face({id(i, j), id(i + 1, j), id(i, j + 1)});
    p.face({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  }
  template <class Kind>  // Kind(i, j): 'q' quad, 't' two triangles, anything else: no face
  static Grid make(int w, int h, Kind kind) {
    Grid g(w, h);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const char k = kind(i, j);
        if (k == 'q') g.cell(i, j);
        if (k == 't') g.split(i, j);
      }
    return g;
  }
};

// Around vertex 0, n faces alternating a quad (0, r_i, x_i, r_i+1) for even i and a triangle
// (0, r_i, r_i+1) for odd i: one vertex cut into n / 2 copies, n / 2 one-quad components.
inline Poly alternating_fan(std::uint32_t n) {
  Poly fan;
  fan.nv = 1 + 2 * n;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t a = 1 + i, z = 1 + (i + 1) % n;
    if (i % 2)
      fan.face({0, a, z});
    else
      fan.face({0, a, 1 + n + i, z});
  }
  return fan;
}

// An n-gon (vertices 0 .. n-1) with one quad on its edge 0-1.
inline Poly ngon_with_a_quad(std::uint32_t n) {
  Poly ngon;
  ngon.nv = n + 2;
  ngon.corners.resize(n);
  std::iota(ngon.corners.begin(), ngon.corners.end(), 0u);
  ngon.offsets.push_back(n);
  ngon.face({1, 0, n, n + 1});
  return ngon;
}

// Faces of any degree from OBJ ("v", "f" lines; negative indices) or OFF.
// A tube of n columns: a band of triangles between two bands of quads, touching both their loops.
inline Poly triangle_band(std::uint32_t n) {
  Poly p;
  auto v = [&](std::uint32_t k, std::uint32_t i) { return k * n + i % n; };
  p.nv = 4 * n;
  for (std::uint32_t k = 0; k < 3; ++k)
    for (std::uint32_t i = 0; i < n; ++i) {
      if (k == 1) {
        p.face({v(k, i), v(k + 1, i), v(k + 1, i + 1)});
        p.face({v(k, i), v(k + 1, i + 1), v(k, i + 1)});
      } else {
        p.face({v(k, i), v(k + 1, i), v(k + 1, i + 1), v(k, i + 1)});
      }
    }
  return p;
}

inline Poly read_faces(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  Poly p;
  if (path.extension() == ".off") {
    std::stringstream text;
    for (std::string line; std::getline(in, line);) text << line.substr(0, line.find('#')) << '\n';
    std::string magic;
    std::uint64_t nv = 0, nf = 0, ne = 0;
    text >> magic >> nv >> nf >> ne;
    p.nv = static_cast<std::uint32_t>(nv);
    p.positions.resize(3 * nv);
    for (auto& x : p.positions) text >> x;
    for (std::uint64_t f = 0; f < nf; ++f) {
      std::uint32_t d = 0;
      text >> d;
      for (std::uint32_t i = 0; i < d; ++i) {
        std::uint32_t v = 0;
        text >> v;
        p.corners.push_back(v);
      }
      p.offsets.push_back(static_cast<std::uint32_t>(p.corners.size()));
    }
    EXPECT_FALSE(text.fail()) << path;
    return p;
  }
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "v") {
      for (int k = 0; k < 3; ++k) {
        float x = 0;
        ls >> x;
        p.positions.push_back(x);
      }
      ++p.nv;
    } else if (key == "f") {
      for (std::string tok; ls >> tok;) {
        const long i = std::stol(tok.substr(0, tok.find('/')));
        p.corners.push_back(static_cast<std::uint32_t>(i < 0 ? p.nv + i : i - 1));
      }
      p.offsets.push_back(static_cast<std::uint32_t>(p.corners.size()));
    }
  }
  return p;
}

// Each subdivision tag as text whatever the numbering: its name, each vertex index (crease, corner) as
// the vertex's position, each face index (hole) as its corners' positions from the smallest, the
// floats' values and float64 flag, the strings; other tags' integers as they are.
inline std::vector<std::string> tags_by_position(const PolygonMesh& m) {
  const auto at = [&m](std::int64_t v) {
    std::ostringstream o;
    o << '(' << m.positions[3 * v] << ' ' << m.positions[3 * v + 1] << ' ' << m.positions[3 * v + 2] << ')';
    return o.str();
  };
  std::vector<std::string> out;
  for (const SubdivisionTag& t : m.tags) {
    std::ostringstream o;
    o << t.name << (t.float64 ? " f64" : " f32");
    for (const std::int64_t i : t.ints) {
      if (t.name == "crease" || t.name == "corner") {
        o << ' ' << at(i);
      } else if (t.name == "hole") {
        std::vector<std::string> c;
        for (std::uint32_t k = m.face_offsets[i]; k < m.face_offsets[i + 1]; ++k)
          c.push_back(at(m.corners[k]));
        std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
        o << " [";
        for (const std::string& s : c) o << s;
        o << ']';
      } else {
        o << ' ' << i;
      }
    }
    for (const double x : t.floats) o << ' ' << std::hexfloat << x << std::defaultfloat;
    for (const std::string& s : t.strings) o << " '" << s << "'";
    out.push_back(o.str());
  }
  return out;
}

// The same mesh with vertices, faces, texture coordinates, normals and label names renumbered and corner
// lists rotated (positions, exact positions, colours, texture coordinates, normals, their exact values,
// labels and tags follow).
inline PolygonMesh renumbered(const PolygonMesh& m, std::uint32_t seed) {
  std::mt19937 rng(seed);
  const std::size_t nv = m.vertex_count(), nf = m.face_count(), K = m.texcoord_components;
  const std::size_t nt = K ? m.texcoords.size() / K : 0;
  std::vector<std::uint32_t> v(nv), f(nf), t(nt);
  std::iota(v.begin(), v.end(), 0u);
  std::iota(f.begin(), f.end(), 0u);
  std::iota(t.begin(), t.end(), 0u);
  std::shuffle(v.begin(), v.end(), rng);
  std::shuffle(f.begin(), f.end(), rng);
  std::shuffle(t.begin(), t.end(), rng);
  std::vector<std::uint32_t> nn(m.normals.size() / 3);
  std::iota(nn.begin(), nn.end(), 0u);
  std::shuffle(nn.begin(), nn.end(), rng);
  PolygonMesh out;
  out.normals.resize(m.normals.size());
  for (std::size_t i = 0; i < nn.size(); ++i) std::copy_n(&m.normals[3 * i], 3, &out.normals[3 * nn[i]]);
  out.normals64.resize(m.normals64.size());
  for (std::size_t i = 0; i < m.normals64.size() / 3; ++i)
    std::copy_n(&m.normals64[3 * i], 3, &out.normals64[3 * nn[i]]);
  out.positions.resize(m.positions.size());
  for (std::size_t i = 0; i < nv; ++i)
    std::copy_n(&m.positions[3 * i], 3, &out.positions[3 * std::size_t{v[i]}]);
  out.positions64.resize(m.positions64.size());
  for (std::size_t i = 0; i < m.positions64.size() / 3; ++i)
    std::copy_n(&m.positions64[3 * i], 3, &out.positions64[3 * std::size_t{v[i]}]);
  const std::size_t kv = m.vertex_color_components, kf = m.face_color_components;
  out.vertex_color_components = m.vertex_color_components;
  out.vertex_colors.resize(m.vertex_colors.size());
  for (std::size_t i = 0; i < nv && kv; ++i)
    std::copy_n(&m.vertex_colors[kv * i], kv, &out.vertex_colors[kv * v[i]]);
  out.vertex_colors64.resize(m.vertex_colors64.size());
  for (std::size_t i = 0; i < nv && kv && !m.vertex_colors64.empty(); ++i)
    std::copy_n(&m.vertex_colors64[kv * i], kv, &out.vertex_colors64[kv * v[i]]);
  out.face_color_components = m.face_color_components;
  out.face_colors.resize(m.face_colors.size());
  for (std::size_t g = 0; g < nf && kf; ++g)
    std::copy_n(&m.face_colors[kf * f[g]], kf, &out.face_colors[kf * g]);
  out.face_colors64.resize(m.face_colors64.size());
  for (std::size_t g = 0; g < nf && kf && !m.face_colors64.empty(); ++g)
    std::copy_n(&m.face_colors64[kf * f[g]], kf, &out.face_colors64[kf * g]);
  out.texcoord_components = m.texcoord_components;
  out.texcoords.resize(m.texcoords.size());
  for (std::size_t i = 0; i < nt; ++i) std::copy_n(&m.texcoords[K * i], K, &out.texcoords[K * t[i]]);
  out.texcoords64.resize(m.texcoords64.size());
  for (std::size_t i = 0; i < nt && !m.texcoords64.empty(); ++i)
    std::copy_n(&m.texcoords64[K * i], K, &out.texcoords64[K * t[i]]);
  out.face_offsets.assign(1, 0);
  for (std::size_t g = 0; g < nf; ++g) {
    const std::uint32_t from = f[g], b = m.face_offsets[from], d = m.degree(from);
    const std::uint32_t r = static_cast<std::uint32_t>(rng() % d);
    for (std::uint32_t i = 0; i < d; ++i) {
      const std::uint32_t c = b + (i + r) % d;
      out.corners.push_back(v[m.corners[c]]);
      if (K)
        out.corner_texcoords.push_back(m.corner_texcoords[c] == kInvalid ? kInvalid
                                                                         : t[m.corner_texcoords[c]]);
      if (!m.corner_normals.empty())
        out.corner_normals.push_back(m.corner_normals[c] == kInvalid ? kInvalid : nn[m.corner_normals[c]]);
    }
    out.face_offsets.push_back(static_cast<std::uint32_t>(out.corners.size()));
  }
  for (auto [from, to] : {std::pair{&m.objects, &out.objects}, std::pair{&m.groups, &out.groups},
                          std::pair{&m.materials, &out.materials}, std::pair{&m.smoothing, &out.smoothing}}) {
    std::vector<std::uint32_t> n(from->names.size());
    std::iota(n.begin(), n.end(), 0u);
    std::shuffle(n.begin(), n.end(), rng);
    to->names.resize(n.size());
    for (std::size_t i = 0; i < n.size(); ++i) to->names[n[i]] = from->names[i];
    if (from->face.empty()) continue;
    to->face.resize(nf);
    for (std::size_t g = 0; g < nf; ++g) {
      const std::uint32_t l = from->face[f[g]];
      to->face[g] = l == kInvalid ? kInvalid : n[l];
    }
  }
  out.material_libraries = m.material_libraries;
  out.kept_lines = m.kept_lines;
  std::vector<std::uint32_t> face_to(nf);
  for (std::uint32_t g = 0; g < nf; ++g) face_to[f[g]] = g;
  for (SubdivisionTag tag : m.tags) {
    for (std::int64_t& i : tag.ints) {
      if (tag.name == "crease" || tag.name == "corner") i = v[static_cast<std::size_t>(i)];
      if (tag.name == "hole") i = face_to[static_cast<std::size_t>(i)];
    }
    out.tags.push_back(std::move(tag));
  }
  return out;
}

// The same mesh with vertices and faces renumbered and every corner list rotated (positions follow).
inline Poly shuffled(const Poly& p, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint32_t> vperm(p.nv), order(p.face_count());
  std::iota(vperm.begin(), vperm.end(), 0u);
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(vperm.begin(), vperm.end(), rng);
  std::shuffle(order.begin(), order.end(), rng);
  Poly out;
  out.nv = p.nv;
  if (!p.positions.empty()) {
    out.positions.resize(p.positions.size());
    for (std::uint32_t v = 0; v < p.nv; ++v)
      for (int k = 0; k < 3; ++k) out.positions[3 * vperm[v] + k] = p.positions[3 * v + k];
  }
  for (std::uint32_t f : order) {
    const std::uint32_t d = p.degree(f), r = rng() % d;
    for (std::uint32_t i = 0; i < d; ++i) out.corners.push_back(vperm[p.corners[p.offsets[f] + (i + r) % d]]);
    out.offsets.push_back(static_cast<std::uint32_t>(out.corners.size()));
  }
  return out;
}

// Per vertex its number of distinct neighbours (edges), sorted: an isomorphism invariant.
inline std::vector<std::uint32_t> valences(const Poly& x) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> e;
  for (std::uint32_t f = 0; f < x.face_count(); ++f)
    for (std::uint32_t i = 0, d = x.degree(f); i < d; ++i) {
      const std::uint32_t a = x.corners[x.offsets[f] + i], b = x.corners[x.offsets[f] + (i + 1) % d];
      e.insert({std::min(a, b), std::max(a, b)});
    }
  std::vector<std::uint32_t> n(x.nv, 0);
  for (const auto& [a, b] : e) ++n[a], ++n[b];
  std::sort(n.begin(), n.end());
  return n;
}

// The diagonal between two triangles (p q r), (q s r) flipped to (p q s), (p s r), where that changes
// the sorted vertex valences (so the result is surely not isomorphic) and p-s is no edge yet.
inline bool flip_a_diagonal(const Poly& m, Poly& out) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> faces_of;  // directed edge
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::uint32_t f = 0; f < m.face_count(); ++f)
    for (std::uint32_t i = 0, d = m.degree(f); i < d; ++i) {
      const std::uint32_t a = m.corners[m.offsets[f] + i], b = m.corners[m.offsets[f] + (i + 1) % d];
      faces_of[{a, b}].push_back(f);
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  const auto before = valences(m);
  for (std::uint32_t f = 0; f < m.face_count(); ++f) {
    if (m.degree(f) != 3) continue;
    for (std::uint32_t i = 0; i < 3; ++i) {
      const std::uint32_t* t = &m.corners[m.offsets[f]];
      const std::uint32_t p = t[i], q = t[(i + 1) % 3], r = t[(i + 2) % 3];
      const auto back = faces_of.find({r, q});
      if (back == faces_of.end() || back->second.size() != 1 || faces_of[{q, r}].size() != 1) continue;
      const std::uint32_t g = back->second[0];
      if (g == f || m.degree(g) != 3) continue;
      std::uint32_t s = 0;
      for (std::uint32_t k = m.offsets[g]; k < m.offsets[g + 1]; ++k)
        if (m.corners[k] != q && m.corners[k] != r) s = m.corners[k];
      if (s == p || edges.count({std::min(p, s), std::max(p, s)})) continue;
      out = m;
      std::uint32_t* a = &out.corners[out.offsets[f]];
      std::uint32_t* b = &out.corners[out.offsets[g]];
      a[0] = p, a[1] = q, a[2] = s;
      b[0] = p, b[1] = s, b[2] = r;
      if (valences(out) != before) return true;
    }
  }
  return false;
}

// Whether the rules of qsp/submesh.h accept the mesh; a refusal must be of what is not a mesh (a vertex
// out of range, a face repeating one; test_submesh checks which files those are against their manifest).
inline bool cuttable(const Poly& p) {
  try {
    (void)cut_manifold(p.offsets, p.corners, p.nv);
    return true;
  } catch (const Error& e) {
    EXPECT_TRUE(e.code() == ErrorCode::kDegenerateFace || e.code() == ErrorCode::kBadIndex) << e.what();
    return false;
  }
}

// A named polygon mesh.
struct PolyCase {
  std::string name;
  Poly p;
};

// Hand-made polygon meshes by name (positions empty): the hand-checked cases of tests/test_submesh.cpp and
// tests/test_regions.cpp, and random mixtures of quads, triangle pairs and holes.
inline std::vector<PolyCase> hand_polygon_cases() {
  std::vector<PolyCase> out;
  out.push_back({"notch_with_triangles", Grid::make(5, 4, [](int i, int j) {
                                           return i == 0 && j == 3 ? '.' : j == 1 && i <= 1 ? 't' : 'q';
                                         }).p});
  out.push_back({"triangle_hole_in_a_grid",
                 Grid::make(3, 3, [](int i, int j) { return i == 1 && j == 1 ? 't' : 'q'; }).p});
  {
    Poly p;  // a closed "UV sphere": two triangle-fan poles, two rows of quads
    const std::uint32_t n = 6, north = 18, south = 19;
    auto ring = [&](std::uint32_t k, std::uint32_t i) { return k * n + i % n; };
    p.nv = 3 * n + 2;
    for (std::uint32_t i = 0; i < n; ++i) p.face({north, ring(0, i), ring(0, i + 1)});
    for (std::uint32_t k = 0; k < 2; ++k)
      for (std::uint32_t i = 0; i < n; ++i)
        p.face({ring(k, i), ring(k + 1, i), ring(k + 1, i + 1), ring(k, i + 1)});
    for (std::uint32_t i = 0; i < n; ++i) p.face({south, ring(2, i + 1), ring(2, i)});
    out.push_back({"uv_sphere_poles", p});
  }
  {
    Grid g =
        Grid::make(4, 4, [](int i, int j) { return (i == 1 || i == 2) && (j == 1 || j == 2) ? '.' : 'q'; });
    Poly& p = g.p;
    const std::uint32_t m = g.id(2, 2), pe = 25, pn = 26, pw = 27, ps = 28;
    p.nv = 29;
    p.face({pe, g.id(3, 2), g.id(3, 3)});
    p.face({m, pe, g.id(3, 3), g.id(2, 3), pn});
    p.face({m, pn, g.id(2, 3), g.id(1, 3), g.id(1, 2), pw});
    p.face({m, pw, g.id(1, 2), g.id(1, 1), g.id(2, 1), ps});
    p.face({m, ps, g.id(2, 1), g.id(3, 1), g.id(3, 2), pe});
    out.push_back({"ngon_region_with_interior", p});
  }
  // A 2x2 block of triangle pairs in a 4x4 quad grid: 8 triangles around the interior vertex (2, 2).
  out.push_back(
      {"triangle_block_with_interior_vertex",
       Grid::make(4, 4, [](int i, int j) { return i >= 1 && i <= 2 && j >= 1 && j <= 2 ? 't' : 'q'; }).p});
  // A 4x4 block in an 8x8 grid: 9 interior vertices, some reached again off the traversal's front.
  out.push_back({"triangle_block_4x4", Grid::make(8, 8, [](int i, int j) {
                                         return i >= 2 && i <= 5 && j >= 2 && j <= 5 ? 't' : 'q';
                                       }).p});
  out.push_back({"vertex_cut_apart_by_triangles", Grid::make(4, 4, [](int i, int j) {
                                                    return (i == 2 && j == 2) || (i == 1 && j == 1) ? 't'
                                                                                                    : 'q';
                                                  }).p});
  {
    Grid g = Grid::make(2, 2, [](int, int) { return 'q'; });
    g.p.nv = 11;
    g.p.face({g.id(1, 0), g.id(1, 1), 10, 9});
    out.push_back({"nonmanifold_edge_three_quads", g.p});
  }
  {
    Grid g = Grid::make(3, 3, [](int i, int j) { return i == 1 && j == 1 ? '.' : 'q'; });
    g.p.face({g.id(1, 1), g.id(1, 2), g.id(2, 2), g.id(2, 1)});
    out.push_back({"misoriented_face", g.p});
  }
  {
    Grid a = Grid::make(2, 2, [](int, int) { return 'q'; });
    Poly p = a.p;
    auto b = [&](int x, int y) {
      return x == 1 && y == 0 ? a.id(1, 2) : static_cast<std::uint32_t>(9 + y * 3 + x);
    };
    p.nv = 18;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) p.face({b(i, j), b(i + 1, j), b(i + 1, j + 1), b(i, j + 1)});
    out.push_back({"bow_tie_vertex", p});
  }
  {
    Poly p;
    p.nv = 8;
    for (std::uint32_t i = 0; i < 3; ++i) p.face({i, i + 1, 5 + i, 4 + i});
    p.face({3, 4, 0, 7});
    out.push_back({"mobius_band", p});
  }
  {
    Poly p;
    p.nv = 4;
    p.face({0, 2, 1});
    p.face({0, 1, 3});
    p.face({1, 2, 3});
    p.face({2, 0, 3});
    out.push_back({"tetrahedron", p});
  }
  { out.push_back({"triangle_band_two_loops", triangle_band(5)}); }
  {
    Poly p;
    p.nv = 10;
    const std::uint32_t cube[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                      {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    for (const auto& q : cube) p.face({q[0], q[1], q[2], q[3]});
    p.face({0, 1, 8, 9});
    out.push_back({"fin_on_a_closed_surface", p});
  }
  out.push_back({"checkerboard", Grid::make(7, 5, [](int i, int j) { return (i + j) % 2 ? 't' : 'q'; }).p});
  for (std::uint32_t seed = 1; seed <= 8; ++seed) {
    std::mt19937 rng(seed);
    const char kinds[] = {'q', 'q', 'q', 't', '.'};
    out.push_back({"random_mix_" + std::to_string(seed),
                   Grid::make(9, 7, [&](int, int) { return kinds[rng() % 5]; }).p});
  }
  return out;
}

}  // namespace qsp::testing
