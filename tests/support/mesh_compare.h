// Field-by-field equality of two qsp::Mesh, numbers bit for bit, for the round-trip tests.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "qsp/polymesh.h"

namespace qsp::testing {

inline bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), 4 * a.size()) == 0);
}
inline bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), 8 * a.size()) == 0);
}

// Empty when equal, else what differs first.
inline std::string numbers_difference(const Numbers& a, const Numbers& b) {
  if (a.precision != b.precision)
    return "precision " + std::to_string(int(a.precision)) + " vs " + std::to_string(int(b.precision));
  if (!same_bits(a.f32, b.f32))
    return "float32 values (" + std::to_string(a.size()) + " vs " + std::to_string(b.size()) + ")";
  if (!same_bits(a.f64, b.f64)) return "float64 values";
  if (a.decimals.size() != b.decimals.size()) return "decimal count";
  for (std::size_t i = 0; i < a.decimals.size(); ++i) {
    const DecimalNumber &x = a.decimals[i], &y = b.decimals[i];
    if (x.index != y.index || x.negative != y.negative || x.exponent != y.exponent || x.digits != y.digits)
      return "decimal " + std::to_string(i);
  }
  return "";
}

inline void expect_same_labels(const FaceLabels& a, const FaceLabels& b, const char* what) {
  EXPECT_EQ(a.face, b.face) << what;
  EXPECT_EQ(a.names, b.names) << what;
}

inline void expect_same_properties(const std::vector<Property>& a, const std::vector<Property>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_EQ(a[i].type, b[i].type) << a[i].name;
    EXPECT_EQ(a[i].list, b[i].list) << a[i].name;
    if (a[i].list) {
      EXPECT_EQ(a[i].count_type, b[i].count_type) << a[i].name;
    }
    EXPECT_EQ(a[i].offsets, b[i].offsets) << a[i].name;
    EXPECT_EQ(numbers_difference(a[i].values, b[i].values), "") << a[i].name;
  }
}

inline void expect_same_fields(const std::vector<PlyField>& a, const std::vector<PlyField>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].role, b[i].role) << a[i].name;
    EXPECT_EQ(a[i].index, b[i].index) << a[i].name;
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_EQ(a[i].type, b[i].type) << a[i].name;
  }
}

// Every field of the model, numbers bit for bit.
inline void expect_same_mesh(const Mesh& a, const Mesh& b) {
  EXPECT_EQ(numbers_difference(a.positions, b.positions), "") << "positions";
  EXPECT_EQ(numbers_difference(a.vertex_colors, b.vertex_colors), "") << "vertex colours";
  EXPECT_EQ(a.vertex_color_components, b.vertex_color_components);
  EXPECT_EQ(numbers_difference(a.vertex_weights, b.vertex_weights), "") << "vertex weights";
  EXPECT_EQ(a.face_offsets, b.face_offsets);
  EXPECT_EQ(a.corner_vertices, b.corner_vertices);
  EXPECT_EQ(numbers_difference(a.texcoords, b.texcoords), "") << "texture coordinates";
  if (!a.texcoords.empty()) {
    EXPECT_EQ(a.texcoord_components, b.texcoord_components);
  }
  EXPECT_EQ(a.corner_texcoords, b.corner_texcoords);
  EXPECT_EQ(numbers_difference(a.normals, b.normals), "") << "normals";
  EXPECT_EQ(a.corner_normals, b.corner_normals);
  EXPECT_EQ(numbers_difference(a.face_colors, b.face_colors), "") << "face colours";
  EXPECT_EQ(a.face_color_components, b.face_color_components);
  expect_same_labels(a.objects, b.objects, "objects");
  expect_same_labels(a.groups, b.groups, "groups");
  expect_same_labels(a.materials, b.materials, "materials");
  expect_same_labels(a.smoothing, b.smoothing, "smoothing");
  EXPECT_EQ(a.material_libraries, b.material_libraries);
  ASSERT_EQ(a.tags.size(), b.tags.size());
  for (std::size_t i = 0; i < a.tags.size(); ++i) {
    EXPECT_EQ(a.tags[i].name, b.tags[i].name);
    EXPECT_EQ(a.tags[i].ints, b.tags[i].ints) << a.tags[i].name;
    EXPECT_EQ(numbers_difference(a.tags[i].floats, b.tags[i].floats), "") << a.tags[i].name;
    EXPECT_EQ(a.tags[i].strings, b.tags[i].strings) << a.tags[i].name;
  }
  EXPECT_EQ(a.comments, b.comments);
  EXPECT_EQ(a.verbatim, b.verbatim);
  expect_same_properties(a.vertex_properties, b.vertex_properties);
  expect_same_properties(a.face_properties, b.face_properties);
  ASSERT_EQ(a.statements.size(), b.statements.size());
  for (std::size_t i = 0; i < a.statements.size(); ++i) {
    EXPECT_EQ(a.statements[i].kind, b.statements[i].kind) << "statement " << i;
    EXPECT_EQ(a.statements[i].value, b.statements[i].value) << "statement " << i;
  }
  EXPECT_EQ(a.ply.format, b.ply.format);
  EXPECT_EQ(a.ply.faces_first, b.ply.faces_first);
  expect_same_fields(a.ply.vertex, b.ply.vertex);
  expect_same_fields(a.ply.face, b.ply.face);
  EXPECT_EQ(a.ply.obj_info, b.ply.obj_info);
}

}  // namespace qsp::testing
