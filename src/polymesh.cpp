// The polygon mesh model: its invariants, dropping categories of data, and the bridges to QuadMesh and
// the codec's PolygonMesh.
#include "qsp/polymesh.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "plural.h"
#include "polymesh_check.h"
#include "qsp/error.h"
#include "qsp/mesh.h"

namespace qsp {
namespace {
using detail::plural;

[[noreturn]] void invalid(const std::string& what) {
  throw Error(ErrorCode::kUsage, "invalid mesh: " + what);
}

void check_numbers(const Numbers& n, const char* name) {
  const std::string s = name;
  if (n.precision == Precision::kFloat32 && (!n.f64.empty() || !n.decimals.empty()))
    invalid(s + ": float32 numbers with float64 or decimal values");
  if (n.precision != Precision::kFloat32 && n.f64.size() != n.f32.size())
    invalid(s + ": " + std::to_string(n.f64.size()) + " float64 values for " + std::to_string(n.f32.size()));
  if (n.precision != Precision::kDecimal && !n.decimals.empty()) invalid(s + ": decimals without kDecimal");
  for (std::size_t i = 0; i < n.decimals.size(); ++i) {
    const DecimalNumber& d = n.decimals[i];
    if (d.index >= n.size() || (i > 0 && d.index <= n.decimals[i - 1].index))
      invalid(s + ": decimal " + std::to_string(i) + " has index " + std::to_string(d.index));
    if (d.digits.empty() || d.digits.front() == '0' || d.digits.back() == '0' ||
        d.digits.find_first_not_of("0123456789") != std::string::npos)
      invalid(s + ": decimal " + std::to_string(i) + " has malformed digits");
  }
}

void check_grouped(const Numbers& n, std::size_t per, std::size_t count, const char* name) {
  check_numbers(n, name);
  if (!n.empty() && n.size() != per * count)
    invalid(std::string(name) + ": " + std::to_string(n.size()) + " values for " + std::to_string(count) +
            " elements of " + std::to_string(per));
}

void check_corner_indices(const std::vector<std::uint32_t>& c, std::size_t corners, std::size_t count,
                          const char* name) {
  if (c.empty()) return;
  if (c.size() != corners)
    invalid(std::string(name) + ": " + std::to_string(c.size()) + " entries for " + std::to_string(corners) +
            " corners");
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c[i] != kInvalid && c[i] >= count)
      invalid(std::string(name) + ": corner " + std::to_string(i) + " refers to " + std::to_string(c[i]) +
              " of " + std::to_string(count));
  }
}

void check_labels(const FaceLabels& l, std::size_t faces, const char* name) {
  if (!l.face.empty() && l.face.size() != faces)
    invalid(std::string(name) + ": " + std::to_string(l.face.size()) + " entries for " +
            std::to_string(faces) + " faces");
  for (std::size_t f = 0; f < l.face.size(); ++f) {
    if (l.face[f] != kInvalid && l.face[f] >= l.names.size())
      invalid(std::string(name) + ": face " + std::to_string(f) + " has label " + std::to_string(l.face[f]) +
              " of " + std::to_string(l.names.size()));
  }
}

void check_properties(const std::vector<Property>& props, std::size_t count, const char* name) {
  for (const Property& p : props) {
    const std::string s = std::string(name) + " '" + p.name + "'";
    check_numbers(p.values, s.c_str());
    if (!p.list) {
      if (!p.offsets.empty()) invalid(s + ": a scalar with list offsets");
      if (p.values.size() != count) invalid(s + ": " + std::to_string(p.values.size()) + " values");
      continue;
    }
    if (p.offsets.size() != count + 1 || p.offsets.front() != 0 || p.offsets.back() != p.values.size())
      invalid(s + ": list offsets do not match its values");
    for (std::size_t i = 0; i + 1 < p.offsets.size(); ++i) {
      if (p.offsets[i] > p.offsets[i + 1]) invalid(s + ": list offsets decrease");
    }
  }
}

// Removes the statements of `kinds` and joins the runs that meet.
void remove_statements(std::vector<Statement>& st, std::initializer_list<ObjStatement> kinds) {
  std::vector<Statement> out;
  out.reserve(st.size());
  for (const Statement& s : st) {
    if (std::find(kinds.begin(), kinds.end(), s.kind) != kinds.end()) continue;
    const bool run = s.kind == ObjStatement::kVertex || s.kind == ObjStatement::kTexcoord ||
                     s.kind == ObjStatement::kNormal || s.kind == ObjStatement::kFace ||
                     s.kind == ObjStatement::kMaterialLibrary || s.kind == ObjStatement::kTag ||
                     s.kind == ObjStatement::kComment || s.kind == ObjStatement::kVerbatim;
    if (run && !out.empty() && out.back().kind == s.kind) {
      out.back().value += s.value;
    } else {
      out.push_back(s);
    }
  }
  st = std::move(out);
}

// Removes the statements of the data kinds in `categories` (the OBJ statements each kind writes).
void remove_category_statements(std::vector<Statement>& st, unsigned categories) {
  if (categories & kCategoryUv) remove_statements(st, {ObjStatement::kTexcoord});
  if (categories & kCategoryNormal) remove_statements(st, {ObjStatement::kNormal});
  if (categories & kCategoryGroup) remove_statements(st, {ObjStatement::kObject, ObjStatement::kGroup});
  if (categories & kCategoryMaterial)
    remove_statements(st, {ObjStatement::kMaterial, ObjStatement::kMaterialLibrary});
  if (categories & kCategorySmoothing) remove_statements(st, {ObjStatement::kSmoothing});
  if (categories & kCategoryTag) remove_statements(st, {ObjStatement::kTag});
  if (categories & kCategoryComment) remove_statements(st, {ObjStatement::kComment});
  if (categories & kCategoryExtra) remove_statements(st, {ObjStatement::kVerbatim});
}

void remove_fields(std::vector<PlyField>& fields, PlyRole role) {
  std::erase_if(fields, [role](const PlyField& f) { return f.role == role; });
}

}  // namespace

Numbers numbers_from_float32(std::vector<float> values) {
  Numbers n;
  n.f32 = std::move(values);
  return n;
}

Numbers numbers_from_float64(const std::vector<double>& values) {
  Numbers n;
  n.precision = Precision::kFloat64;
  n.f64 = values;
  n.f32.reserve(values.size());
  for (const double d : values) n.f32.push_back(static_cast<float>(d));
  return n;
}

TagIndices tag_indices(std::string_view name) {
  if (name == "crease") return TagIndices::kEdges;
  if (name == "corner") return TagIndices::kVertices;
  if (name == "hole") return TagIndices::kFaces;
  if (name == "interpolateboundary" || name == "facevaryinginterpolateboundary" ||
      name == "facevaryingpropagatecorners" || name == "creasemethod" || name == "smoothtriangles")
    return TagIndices::kNone;
  return TagIndices::kUnknown;
}

void renumber_tags(std::vector<SubdivisionTag>& tags, std::span<const std::uint32_t> vertex,
                   std::span<const std::uint32_t> face) {
  for (std::size_t t = 0; t < tags.size(); ++t) {
    SubdivisionTag& tag = tags[t];
    const auto fail = [&](const std::string& what) {
      throw Error(ErrorCode::kUsage, "tag " + std::to_string(t) + " ('" + tag.name + "') " + what);
    };
    const TagIndices kind = tag_indices(tag.name);
    if (kind == TagIndices::kNone) continue;
    if (kind == TagIndices::kUnknown) fail("indexes what qsp cannot renumber");
    if (kind == TagIndices::kEdges && tag.ints.size() % 2) fail("has an odd number of vertex indices");
    const std::span<const std::uint32_t> map = kind == TagIndices::kFaces ? face : vertex;
    for (std::int64_t& i : tag.ints) {
      if (i < 0 || static_cast<std::uint64_t>(i) >= map.size())
        fail("has index " + std::to_string(i) + " out of range");
      i = map[static_cast<std::size_t>(i)];
    }
  }
}

std::string_view scalar_type_name(ScalarType t) {
  static constexpr std::string_view kNames[] = {"char", "uchar", "short", "ushort",
                                                "int",  "uint",  "float", "double"};
  return kNames[static_cast<std::size_t>(t)];
}

void detail::check_mesh_arrays(const Mesh& m) {
  check_numbers(m.positions, "positions");
  if (m.positions.size() % 3 != 0) invalid("positions: not 3 per vertex");
  const std::size_t v = m.vertex_count();
  if (v > 0xFFFFFFFEu) invalid("more than 2^32 - 2 vertices");
  if (m.face_offsets.empty() && !m.corner_vertices.empty()) invalid("corners without face offsets");
  if (!m.face_offsets.empty() && (m.face_offsets.front() != 0 || m.face_offsets.back() != m.corner_count()))
    invalid("face offsets do not span the corners");
  const std::size_t f = m.face_count();
  for (std::size_t i = 0; i < f; ++i) {
    if (m.face_offsets[i + 1] < m.face_offsets[i] || m.degree(i) < 3)
      invalid("face " + std::to_string(i) + " has fewer than 3 corners");
  }
  for (std::size_t c = 0; c < m.corner_count(); ++c) {
    if (m.corner_vertices[c] >= v)
      invalid("corner " + std::to_string(c) + " refers to vertex " + std::to_string(m.corner_vertices[c]));
  }
  if (m.vertex_color_components != 0 && m.vertex_color_components != 3 && m.vertex_color_components != 4)
    invalid("vertex colours have " + std::to_string(m.vertex_color_components) + " components");
  check_grouped(m.vertex_colors, m.vertex_color_components, v, "vertex colours");
  if (m.vertex_colors.empty() != (m.vertex_color_components == 0 || v == 0))
    invalid("vertex colours: components without colours or colours without components");
  check_grouped(m.vertex_weights, 1, v, "vertex weights");
  if (m.texcoord_components < 1 || m.texcoord_components > 3)
    invalid("texture coordinates: 1 to 3 components");
  check_numbers(m.texcoords, "texture coordinates");
  if (m.texcoords.size() % m.texcoord_components != 0) invalid("texture coordinates: a partial one");
  check_corner_indices(m.corner_texcoords, m.corner_count(), m.texcoords.size() / m.texcoord_components,
                       "corner texture coordinates");
  check_numbers(m.normals, "normals");
  if (m.normals.size() % 3 != 0) invalid("normals: not 3 per normal");
  check_corner_indices(m.corner_normals, m.corner_count(), m.normals.size() / 3, "corner normals");
  if (m.face_color_components > 4 || m.face_color_components == 2)
    invalid("face colours have " + std::to_string(m.face_color_components) + " components");
  check_grouped(m.face_colors, m.face_color_components, f, "face colours");
  if (m.face_colors.empty() != (m.face_color_components == 0 || f == 0))
    invalid("face colours: components without colours or colours without components");
  check_labels(m.objects, f, "objects");
  check_labels(m.groups, f, "groups");
  check_labels(m.materials, f, "materials");
  check_labels(m.smoothing, f, "smoothing groups");
  for (const Tag& t : m.tags) check_numbers(t.floats, ("tag " + t.name).c_str());
  check_properties(m.vertex_properties, v, "vertex property");
  check_properties(m.face_properties, f, "face property");

  // The statement order: runs add up to their arrays, labels are in range.
  if (!m.statements.empty()) {
    std::uint64_t n[12] = {};
    for (const Statement& s : m.statements) {
      const auto k = static_cast<std::size_t>(s.kind);
      if (k >= 12) invalid("statement of unknown kind");
      const FaceLabels* l = s.kind == ObjStatement::kObject      ? &m.objects
                            : s.kind == ObjStatement::kGroup     ? &m.groups
                            : s.kind == ObjStatement::kMaterial  ? &m.materials
                            : s.kind == ObjStatement::kSmoothing ? &m.smoothing
                                                                 : nullptr;
      if (l && s.value >= l->names.size()) invalid("statement refers to label " + std::to_string(s.value));
      n[k] += l ? 1 : s.value;
    }
    const auto expect = [&](ObjStatement k, std::uint64_t want, const char* what) {
      if (n[static_cast<std::size_t>(k)] != want)
        invalid(std::string("statements: ") + std::to_string(n[static_cast<std::size_t>(k)]) + " " + what +
                " for " + std::to_string(want));
    };
    expect(ObjStatement::kVertex, v, "vertices");
    expect(ObjStatement::kTexcoord, m.texcoords.size() / m.texcoord_components, "texture coordinates");
    expect(ObjStatement::kNormal, m.normals.size() / 3, "normals");
    expect(ObjStatement::kFace, f, "faces");
    expect(ObjStatement::kMaterialLibrary, m.material_libraries.size(), "material libraries");
    expect(ObjStatement::kTag, m.tags.size(), "tags");
    expect(ObjStatement::kComment, m.comments.size(), "comments");
    expect(ObjStatement::kVerbatim, m.verbatim.size(), "verbatim lines");
  }
  for (const auto* fields : {&m.ply.vertex, &m.ply.face}) {
    for (const PlyField& fl : *fields) {
      const auto& props = fields == &m.ply.vertex ? m.vertex_properties : m.face_properties;
      if (fl.role == PlyRole::kProperty && fl.index >= props.size())
        invalid("PLY field '" + fl.name + "' refers to property " + std::to_string(fl.index));
      if (fl.role != PlyRole::kProperty && fl.index > 3)
        invalid("PLY field '" + fl.name + "' has component " + std::to_string(fl.index));
    }
  }
}

void check_mesh(const Mesh& m) {
  detail::check_mesh_arrays(m);
  // A vertex repeated within a face: mark each corner's vertex with its face (once per vertex).
  std::vector<std::uint32_t> seen(m.vertex_count(), kInvalid);
  for (std::size_t i = 0; i < m.face_count(); ++i) {
    for (std::uint32_t c = m.face_offsets[i]; c < m.face_offsets[i + 1]; ++c) {
      const std::uint32_t x = m.corner_vertices[c];
      if (seen[x] == i) invalid("face " + std::to_string(i) + " repeats vertex " + std::to_string(x));
      seen[x] = static_cast<std::uint32_t>(i);
    }
  }
}

std::string_view category_name(unsigned category) {
  for (const CategoryName& c : kCategoryNames) {
    if (c.category == category) return c.name;
  }
  return {};
}

std::string category_list(unsigned categories, std::string_view separator) {
  std::string out;
  for (const CategoryName& c : kCategoryNames) {
    if (!(categories & c.category)) continue;
    if (!out.empty()) out += separator;
    out += c.name;
  }
  return out;
}

unsigned parse_categories(std::string_view list) {
  unsigned out = 0;
  std::size_t at = 0;
  while (at <= list.size()) {
    std::size_t comma = list.find(',', at);
    if (comma == std::string_view::npos) comma = list.size();
    const std::string_view name = list.substr(at, comma - at);
    const auto* it = std::find_if(std::begin(kCategoryNames), std::end(kCategoryNames),
                                  [&](const CategoryName& c) { return c.name == name; });
    if (it != std::end(kCategoryNames)) {
      out |= it->category;
    } else if (name == "colour") {
      out |= kCategoryColor;
    } else if (name == "all") {
      out |= kCategoryAll;
    } else {
      throw Error(ErrorCode::kUsage, "unknown category '" + std::string(name.substr(0, 40)) + "' (expected " +
                                         category_list(kCategoryAll, ", ") + " or all)");
    }
    at = comma + 1;
  }
  return out;
}

bool Extras::any() const {
  return texcoords || normals || vertex_colors || face_colors || objects || groups || materials ||
         material_libraries || smoothing || tags || comments || verbatim || properties || vertex_weights;
}

std::string Extras::describe() const {
  std::string out;
  const auto item = [&out](std::uint64_t n, const char* one, const char* many) {
    detail::append_count(out, n, one, many);
  };
  item(texcoords, "texture coordinate", "texture coordinates");
  item(normals, "normal", "normals");
  item(vertex_colors, "vertex colour", "vertex colours");
  item(face_colors, "face colour", "face colours");
  item(objects, "object", "objects");
  item(groups, "group", "groups");
  item(materials, "material", "materials");
  item(material_libraries, "material library", "material libraries");
  item(smoothing, "smoothing group", "smoothing groups");
  item(tags, "subdivision tag", "subdivision tags");
  item(comments, "comment line", "comment lines");
  item(verbatim, "verbatim line", "verbatim lines");
  item(properties, "PLY property", "PLY properties");
  item(vertex_weights, "vertex weight", "vertex weights");
  return out;
}

Extras extras(const Mesh& m, unsigned c) {
  Extras e;
  if (c & kCategoryUv) e.texcoords = m.texcoords.size() / std::max<std::size_t>(m.texcoord_components, 1);
  if (c & kCategoryNormal) e.normals = m.normals.size() / 3;
  if (c & kCategoryColor) {
    e.vertex_colors = m.vertex_color_components ? m.vertex_colors.size() / m.vertex_color_components : 0;
    e.face_colors = m.face_color_components ? m.face_colors.size() / m.face_color_components : 0;
  }
  if (c & kCategoryGroup) {
    e.objects = m.objects.names.size();
    e.groups = m.groups.names.size();
  }
  if (c & kCategoryMaterial) {
    e.materials = m.materials.names.size();
    e.material_libraries = m.material_libraries.size();
  }
  if (c & kCategorySmoothing) e.smoothing = m.smoothing.names.size();
  if (c & kCategoryTag) e.tags = m.tags.size();
  if (c & kCategoryComment) e.comments = m.comments.size();
  if (c & kCategoryExtra) {
    e.verbatim = m.verbatim.size();
    e.properties = m.vertex_properties.size() + m.face_properties.size() + m.ply.obj_info.size();
    e.vertex_weights = m.vertex_weights.size();
  }
  return e;
}

Extras drop(Mesh& m, unsigned c) {
  const Extras dropped = extras(m, c);
  if (c & kCategoryUv) {
    m.texcoords = {};
    m.texcoord_components = 2;
    m.corner_texcoords = {};
    remove_fields(m.ply.vertex, PlyRole::kTexcoord);
  }
  if (c & kCategoryNormal) {
    m.normals = {};
    m.corner_normals = {};
    remove_fields(m.ply.vertex, PlyRole::kNormal);
  }
  if (c & kCategoryColor) {
    m.vertex_colors = {};
    m.vertex_color_components = 0;
    m.face_colors = {};
    m.face_color_components = 0;
    remove_fields(m.ply.vertex, PlyRole::kColor);
    remove_fields(m.ply.face, PlyRole::kColor);
  }
  if (c & kCategoryGroup) {
    m.objects = {};
    m.groups = {};
  }
  if (c & kCategoryMaterial) {
    m.materials = {};
    m.material_libraries = {};
  }
  if (c & kCategorySmoothing) {
    m.smoothing = {};
  }
  if (c & kCategoryTag) {
    m.tags = {};
  }
  if (c & kCategoryComment) {
    m.comments = {};
  }
  if (c & kCategoryExtra) {
    m.verbatim = {};
    m.vertex_properties = {};
    m.face_properties = {};
    m.vertex_weights = {};
    m.ply.obj_info = {};
    remove_fields(m.ply.vertex, PlyRole::kProperty);
    remove_fields(m.ply.face, PlyRole::kProperty);
  }
  remove_category_statements(m.statements, c);
  return dropped;
}

unsigned drop(PolygonMesh& m, unsigned c) {
  unsigned had = 0;
  const auto take = [&](unsigned category, bool has, auto&& clear) {
    if (!(c & category) || !has) return;
    had |= category;
    clear();
  };
  take(kCategoryUv, m.texcoord_components != 0, [&] {
    m.texcoord_components = 0;
    m.texcoords = {}, m.texcoords64 = {}, m.corner_texcoords = {};
  });
  take(kCategoryNormal, !m.corner_normals.empty(),
       [&] { m.normals = {}, m.normals64 = {}, m.corner_normals = {}; });
  take(kCategoryColor, m.vertex_color_components || m.face_color_components, [&] {
    m.vertex_color_components = m.face_color_components = 0;
    m.vertex_colors = {}, m.vertex_colors64 = {}, m.face_colors = {}, m.face_colors64 = {};
  });
  take(kCategoryGroup, !m.objects.empty() || !m.groups.empty(), [&] { m.objects = {}, m.groups = {}; });
  take(kCategoryMaterial, !m.materials.empty() || !m.material_libraries.empty(),
       [&] { m.materials = {}, m.material_libraries = {}; });
  take(kCategorySmoothing, !m.smoothing.empty(), [&] { m.smoothing = {}; });
  take(kCategoryTag, !m.tags.empty(), [&] { m.tags = {}; });
  take(kCategoryExtra,
       !m.kept_lines.empty() || !m.vertex_properties.empty() || !m.face_properties.empty() ||
           !m.ply_info.empty(),
       [&] { m.kept_lines = {}, m.vertex_properties = {}, m.face_properties = {}, m.ply_info = {}; });
  remove_category_statements(m.statements, c);
  return had;
}

namespace {

// A property's values as the codec keeps them: each exactly (the nearest binary64 of a kDecimal list).
ValueProperty value_property(std::string name, ScalarType type, Numbers& n) {
  ValueProperty p;
  p.name = std::move(name);
  p.type = type;
  p.float64 =
      n.precision != Precision::kFloat32 && (type == ScalarType::kFloat32 || type == ScalarType::kFloat64);
  p.values.resize(n.size());
  for (std::size_t i = 0; i < n.size(); ++i) p.values[i] = n.approx(i);
  n = {};
  return p;
}

std::vector<ValueProperty> value_properties(std::vector<Property>& props) {
  std::vector<ValueProperty> out;
  for (Property& q : props) {
    ValueProperty& p = out.emplace_back(value_property(std::move(q.name), q.type, q.values));
    p.list = q.list;
    p.count_type = q.count_type;
    p.offsets = std::move(q.offsets);
  }
  return out;
}

}  // namespace

PolygonMesh to_polygon_mesh(Mesh m, unsigned categories) {
  PolygonMesh out;
  if (categories & kCategoryExtra) {
    // The OBJ vertex weight first (the vertex property named ""), then the PLY properties.
    if (!m.vertex_weights.empty())
      out.vertex_properties.push_back(value_property(
          "", m.vertex_weights.precision == Precision::kFloat32 ? ScalarType::kFloat32 : ScalarType::kFloat64,
          m.vertex_weights));
    for (ValueProperty& p : value_properties(m.vertex_properties))
      out.vertex_properties.push_back(std::move(p));
    out.face_properties = value_properties(m.face_properties);
    out.ply_info = std::move(m.ply.obj_info);
  }
  out.positions = std::move(m.positions.f32);
  if (m.positions.precision != Precision::kFloat32) out.positions64 = std::move(m.positions.f64);
  if (categories & kCategoryExtra) out.kept_lines = std::move(m.verbatim);
  if (!m.face_offsets.empty()) out.face_offsets = std::move(m.face_offsets);
  out.corners = std::move(m.corner_vertices);
  if (categories & kCategoryGroup) out.objects = std::move(m.objects), out.groups = std::move(m.groups);
  if (categories & kCategoryMaterial) {
    out.materials = std::move(m.materials);
    out.material_libraries = std::move(m.material_libraries);
  }
  if (categories & kCategorySmoothing) out.smoothing = std::move(m.smoothing);
  if ((categories & kCategoryNormal) && !m.normals.empty()) {
    if (m.normals.precision != Precision::kFloat32) out.normals64 = std::move(m.normals.f64);
    out.normals = std::move(m.normals.f32);
    out.corner_normals = std::move(m.corner_normals);
    if (out.corner_normals.empty()) out.corner_normals.assign(out.corners.size(), kInvalid);
  }
  if (categories & kCategoryTag) {
    for (Tag& t : m.tags) {
      SubdivisionTag& s = out.tags.emplace_back();
      s.name = std::move(t.name);
      s.ints = std::move(t.ints);
      s.float64 = t.floats.precision != Precision::kFloat32;
      for (std::size_t i = 0; i < t.floats.size(); ++i) s.floats.push_back(t.floats.approx(i));
      s.strings = std::move(t.strings);
    }
  }
  if ((categories & kCategoryUv) && !m.texcoords.empty()) {
    out.texcoord_components = m.texcoord_components;
    if (m.texcoords.precision != Precision::kFloat32) out.texcoords64 = std::move(m.texcoords.f64);
    out.texcoords = std::move(m.texcoords.f32);
    out.corner_texcoords = std::move(m.corner_texcoords);
    if (out.corner_texcoords.empty()) out.corner_texcoords.assign(out.corners.size(), kInvalid);
  }
  if (categories & kCategoryColor) {
    out.vertex_color_components = m.vertex_color_components;
    if (m.vertex_colors.precision != Precision::kFloat32)
      out.vertex_colors64 = std::move(m.vertex_colors.f64);
    out.vertex_colors = std::move(m.vertex_colors.f32);
    out.face_color_components = m.face_color_components;
    if (m.face_colors.precision != Precision::kFloat32) out.face_colors64 = std::move(m.face_colors.f64);
    out.face_colors = std::move(m.face_colors.f32);
  }
  // The statement order of what is kept: comments are not (the leading block goes first).
  out.statements = std::move(m.statements);
  remove_statements(out.statements, {ObjStatement::kComment});
  if (!(categories & kCategoryUv) || out.texcoord_components == 0)
    remove_statements(out.statements, {ObjStatement::kTexcoord});
  if (!(categories & kCategoryNormal) || out.normals.empty())
    remove_statements(out.statements, {ObjStatement::kNormal});
  if (!(categories & kCategoryGroup))
    remove_statements(out.statements, {ObjStatement::kObject, ObjStatement::kGroup});
  if (!(categories & kCategoryMaterial))
    remove_statements(out.statements, {ObjStatement::kMaterial, ObjStatement::kMaterialLibrary});
  if (!(categories & kCategorySmoothing)) remove_statements(out.statements, {ObjStatement::kSmoothing});
  if (!(categories & kCategoryTag)) remove_statements(out.statements, {ObjStatement::kTag});
  if (!(categories & kCategoryExtra)) remove_statements(out.statements, {ObjStatement::kVerbatim});
  return out;
}

namespace {

// The values as Numbers: the exact ones where there are (beside their float32s), else the float32s.
Numbers exact_numbers(std::vector<float> f32, const std::vector<double>& f64) {
  return f64.empty() ? numbers_from_float32(std::move(f32)) : numbers_from_float64(f64);
}

// A kept property's values as Numbers: binary64 where a float needs it or an integer is beyond binary32.
Numbers property_numbers(const ValueProperty& p) {
  bool wide = p.float64;
  for (std::size_t i = 0; i < p.values.size() && !wide; ++i)
    wide = !std::isnan(p.values[i]) && static_cast<double>(static_cast<float>(p.values[i])) != p.values[i];
  if (wide) return numbers_from_float64(p.values);
  return numbers_from_float32(std::vector<float>(p.values.begin(), p.values.end()));
}

std::vector<Property> properties_of(std::vector<ValueProperty>& props, Numbers* weights) {
  std::vector<Property> out;
  for (ValueProperty& p : props) {
    if (p.name.empty() && weights) {
      *weights = property_numbers(p);
      continue;
    }
    Property& q = out.emplace_back();
    q.values = property_numbers(p);
    q.name = std::move(p.name);
    q.type = p.type;
    q.list = p.list;
    q.count_type = p.count_type;
    q.offsets = std::move(p.offsets);
  }
  return out;
}

}  // namespace

Mesh from_polygon_mesh(PolygonMesh m) {
  Mesh out;
  out.positions = m.positions64.empty() ? numbers_from_float32(std::move(m.positions))
                                        : numbers_from_float64(m.positions64);
  out.verbatim = std::move(m.kept_lines);
  out.vertex_properties = properties_of(m.vertex_properties, &out.vertex_weights);
  out.face_properties = properties_of(m.face_properties, nullptr);
  out.ply.obj_info = std::move(m.ply_info);
  out.statements = std::move(m.statements);
  out.face_offsets = std::move(m.face_offsets);
  out.corner_vertices = std::move(m.corners);
  if (m.texcoord_components) {
    out.texcoord_components = m.texcoord_components;
    out.texcoords = exact_numbers(std::move(m.texcoords), m.texcoords64);
    out.corner_texcoords = std::move(m.corner_texcoords);
  }
  if (!m.normals.empty() || !m.corner_normals.empty()) {
    out.normals = exact_numbers(std::move(m.normals), m.normals64);
    out.corner_normals = std::move(m.corner_normals);
  }
  out.vertex_color_components = m.vertex_color_components;
  out.vertex_colors = exact_numbers(std::move(m.vertex_colors), m.vertex_colors64);
  out.face_color_components = m.face_color_components;
  out.face_colors = exact_numbers(std::move(m.face_colors), m.face_colors64);
  out.objects = std::move(m.objects);
  out.groups = std::move(m.groups);
  out.materials = std::move(m.materials);
  out.smoothing = std::move(m.smoothing);
  out.material_libraries = std::move(m.material_libraries);
  for (SubdivisionTag& t : m.tags) {
    Tag& w = out.tags.emplace_back();
    w.name = std::move(t.name);
    w.ints = std::move(t.ints);
    if (t.float64) {
      w.floats = numbers_from_float64(t.floats);
    } else {
      w.floats = numbers_from_float32(std::vector<float>(t.floats.begin(), t.floats.end()));
    }
    w.strings = std::move(t.strings);
  }
  return out;
}

QuadMesh to_quad_mesh(const Mesh& m) {
  std::uint64_t non_quads = 0;
  std::string examples;
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    const std::uint32_t d = m.degree(f);
    if (d == 4) continue;
    if (++non_quads <= 3) {
      if (!examples.empty()) examples += ", ";
      examples += "face " + std::to_string(f) + ": " +
                  (d == 3 ? std::string("triangle") : plural(d, "vertex", "vertices"));
    }
  }
  if (non_quads) {
    throw Error(ErrorCode::kNotQuad,
                std::to_string(non_quads) +
                    (non_quads == 1 ? " face is not a quad (" : " faces are not quads (first: ") + examples +
                    (non_quads > 3 ? ", ..." : "") +
                    "); qsp stores quad meshes only and never triangulates or drops faces");
  }
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const float x = m.positions.f32[i];
    if (!std::isfinite(x) || (x == 0.0f && m.positions.approx(i) != 0.0)) {
      throw Error(ErrorCode::kBadNumber, "vertex " + std::to_string(i / 3) +
                                             " has a coordinate outside the float32 range (it does not round "
                                             "to a finite nonzero float)");
    }
  }
  QuadMesh q;
  q.positions = m.positions.f32;
  q.quads = m.corner_vertices;
  return q;
}

Mesh from_quad_mesh(QuadMesh q) {
  Mesh m;
  m.positions = numbers_from_float32(std::move(q.positions));
  const std::size_t f = q.quads.size() / 4;
  m.face_offsets.resize(f + 1);
  for (std::size_t i = 0; i <= f; ++i) m.face_offsets[i] = static_cast<std::uint32_t>(4 * i);
  m.corner_vertices = std::move(q.quads);
  return m;
}

}  // namespace qsp
