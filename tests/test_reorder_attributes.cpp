// reorder_polygons_like keeps every attribute (issue 19: "reorder --like REF IN keeps every attribute of
// IN, in REF's vertex and face order"): over every golden mesh with attributes, a renumbered copy (the
// test's own renumbering: vertices, faces, texture coordinates, normals and label names shuffled, corner
// lists rotated) reordered like the original gives back the original's positions, exact positions,
// colours, each corner's texture coordinate and normal values, each face's labels and colour, and tags
// naming the same vertices and faces. A tag qsp cannot renumber is refused, naming it.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "qsp/error.h"
#include "qsp/match.h"
#include "support/polygon.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> attribute_goldens() {
  std::vector<fs::path> out;
  for (const char* dir : {"texcoords", "labels", "tags", "normals", "colors", "exact", "kept"})
    for (const auto& e : fs::directory_iterator(std::string(QSP_TESTDATA_DIR) + "/golden/" + dir))
      if (e.path().extension() == ".obj") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// The values a corner names in `values` (K per value), or none.
std::vector<float> named(const std::vector<float>& values, std::size_t K,
                         const std::vector<std::uint32_t>& index, std::size_t c) {
  if (index.empty() || index[c] == kInvalid) return {};
  return {values.begin() + static_cast<std::ptrdiff_t>(K * index[c]),
          values.begin() + static_cast<std::ptrdiff_t>(K * index[c] + K)};
}

std::string label(const FaceLabels& l, std::size_t f) {
  return l.face.empty() || l.face[f] == kInvalid ? "-" : l.names[l.face[f]];
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), sizeof(T) * a.size()) == 0);
}

TEST(ReorderAttributes, ARenumberedCopyReorderedLikeTheOriginalIsTheOriginal) {
  int checked = 0;
  for (const fs::path& path : attribute_goldens()) {
    SCOPED_TRACE(path.string());
    const PolygonMesh m = testing::read_obj_polygons(path);
    const PolygonMesh in = testing::renumbered(m, 5);
    const PolygonMatchResult r = match_polygons(prepare_polygon_match(m), prepare_polygon_match(in));
    ASSERT_TRUE(r.isomorphic) << r.reason;
    bool unknown_tag = false;
    for (const SubdivisionTag& t : m.tags)
      unknown_tag = unknown_tag || tag_indices(t.name) == TagIndices::kUnknown;
    if (unknown_tag) {
      try {
        (void)reorder_polygons_like(in, r);
        ADD_FAILURE() << "reordered a tag qsp cannot renumber";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("cannot renumber"), std::string::npos) << e.what();
      }
      continue;
    }
    const PolygonMesh out = reorder_polygons_like(in, r);
    ++checked;
    EXPECT_EQ(out.face_offsets, m.face_offsets);
    EXPECT_EQ(out.corners, m.corners);
    EXPECT_TRUE(same_bits(out.positions, m.positions));
    EXPECT_TRUE(same_bits(out.positions64, m.positions64));
    EXPECT_EQ(out.vertex_color_components, m.vertex_color_components);
    EXPECT_TRUE(same_bits(out.vertex_colors, m.vertex_colors));
    EXPECT_EQ(out.face_color_components, m.face_color_components);
    EXPECT_TRUE(same_bits(out.face_colors, m.face_colors));
    ASSERT_EQ(out.corner_texcoords.size(), m.corner_texcoords.size());
    ASSERT_EQ(out.corner_normals.size(), m.corner_normals.size());
    for (std::size_t c = 0; c < m.corners.size(); ++c) {
      EXPECT_EQ(named(out.texcoords, out.texcoord_components, out.corner_texcoords, c),
                named(m.texcoords, m.texcoord_components, m.corner_texcoords, c))
          << "corner " << c;
      EXPECT_EQ(named(out.normals, 3, out.corner_normals, c), named(m.normals, 3, m.corner_normals, c))
          << "corner " << c;
    }
    EXPECT_EQ(out.texcoords.size(), m.texcoords.size()) << "values no corner names are kept too";
    for (std::size_t f = 0; f < m.face_count(); ++f)
      for (auto [a, b] : {std::pair{&out.objects, &m.objects}, std::pair{&out.groups, &m.groups},
                          std::pair{&out.materials, &m.materials}, std::pair{&out.smoothing, &m.smoothing}})
        EXPECT_EQ(label(*a, f), label(*b, f)) << "face " << f;
    ASSERT_EQ(out.tags.size(), m.tags.size());
    for (std::size_t t = 0; t < m.tags.size(); ++t) {
      EXPECT_EQ(out.tags[t].name, m.tags[t].name);
      EXPECT_EQ(out.tags[t].ints, m.tags[t].ints);
      EXPECT_EQ(out.tags[t].floats, m.tags[t].floats);
    }
    EXPECT_EQ(out.material_libraries, m.material_libraries);
    EXPECT_EQ(out.kept_lines, m.kept_lines);
  }
  EXPECT_GE(checked, 12);
}

}  // namespace
}  // namespace qsp
