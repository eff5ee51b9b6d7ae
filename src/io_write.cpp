// Writers of a Mesh: OBJ (statement for statement when the mesh has its file order), OFF and PLY
// (ASCII or binary, the file's own header layout). Numbers are the shortest text denoting their exact
// value (io_numbers.h). What a format cannot hold is refused by name, with the --drop category.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "beside.h"
#include "io_numbers.h"
#include "polymesh_check.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/polymesh.h"

namespace qsp {
namespace {

using detail::append_number;

void append_uint(std::string& out, std::uint64_t n) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, n);
  out.append(buf, r.ptr);
}

// What a format cannot hold, collected so one message names all of it.
class Refusal {
 public:
  explicit Refusal(const char* format) : format_(format) {}
  void add(std::uint64_t count, const char* what, const char* drop) {
    if (count == 0) return;
    if (!items_.empty()) items_ += ", ";
    items_ +=
        std::to_string(count) + " " + what + (drop ? std::string(" (--drop ") + drop + ")" : std::string());
  }
  void throw_if_any() const {
    if (items_.empty()) return;
    throw Error(ErrorCode::kUnsupported, std::string(format_) + " cannot hold " + items_ +
                                             "; drop them, or write a format that holds them");
  }

 private:
  const char* format_;
  std::string items_;
};

// Whether every corner's `attribute` index is its vertex and there is one value per vertex: data a
// format with per-vertex attributes (OFF, PLY) holds.
bool per_vertex(const Mesh& m, const std::vector<std::uint32_t>& attribute, std::size_t values) {
  return values == m.vertex_count() && (attribute.empty() || attribute == m.corner_vertices);
}

std::uint64_t label_count(const FaceLabels& l) { return l.names.size(); }

// OFF and PLY hold per-vertex attributes only, and no labels, tags or kept lines.
void refuse_what_off_and_ply_lack(Refusal& r, const Mesh& m) {
  if (!m.texcoords.empty() &&
      (!per_vertex(m, m.corner_texcoords, m.texcoords.size() / m.texcoord_components) ||
       m.texcoord_components != 2))
    r.add(m.texcoords.size() / m.texcoord_components, "texture coordinates per corner (seams)", "uv");
  if (!m.normals.empty() && !per_vertex(m, m.corner_normals, m.normals.size() / 3))
    r.add(m.normals.size() / 3, "normals per corner", "normal");
  r.add(label_count(m.objects) + label_count(m.groups), "objects and groups", "group");
  r.add(label_count(m.materials) + m.material_libraries.size(), "materials and material libraries",
        "material");
  r.add(label_count(m.smoothing), "smoothing groups", "smoothing");
  r.add(m.tags.size(), "subdivision tags", "tag");
  r.add(m.verbatim.size(), "lines kept as text", "extra");
  r.add(m.vertex_weights.size(), "vertex weights", "extra");
}

// ----------------------------------------------------------------------------------------------
// OBJ

// The shortest text of floats already written, by their bits (direct-mapped, the newest kept; 16 bytes an
// entry): a decompressed mesh's numbers repeat (mh_base at 14 bits: 57k position numbers, 15k distinct;
// 12-bit UVs: 32k numbers, 4k distinct), and to_chars' shortest form was a quarter of decompressing one.
class FloatTexts {
 public:
  // Room for about `numbers` distinct floats, at most 16,384 (256 KiB).
  explicit FloatTexts(std::size_t numbers)
      : shift_(32 - std::bit_width(std::bit_ceil(std::clamp<std::size_t>(numbers / 2, 256, 16384)) - 1)),
        entries_(std::size_t{1} << (32 - shift_)) {}
  // Writes f's shortest text at `to`, which has room for 32 characters; returns its end.
  char* put(char* to, float f) {
    const auto bits = std::bit_cast<std::uint32_t>(f);
    Entry& e = entries_[(bits * 0x9E3779B1u) >> shift_];
    if (e.length != 0 && e.bits == bits) {
      std::memcpy(to, e.text, sizeof e.text);
      return to + e.length;
    }
    char* const end = std::to_chars(to, to + 32, f).ptr;
    const auto length = static_cast<std::size_t>(end - to);
    if (length <= sizeof e.text) {
      e.bits = bits;
      e.length = static_cast<std::uint8_t>(length);
      std::memcpy(e.text, to, length);
    }
    return end;
  }

 private:
  struct Entry {
    std::uint32_t bits;
    std::uint8_t length;  // 0: empty
    char text[11];        // most floats' shortest texts (at most 15)
  };
  int shift_;
  std::vector<Entry> entries_;
};

// A line built in a buffer on the stack and appended once: appending each word and space to the
// string (a capacity check each) was a third of writing mh_base's face lines. The user calls flush()
// before writing to the string itself and at the end (not the destructor: an append there that ran out
// of memory would end the process instead of reaching the caller's error).
class Line {
 public:
  explicit Line(std::string& out, FloatTexts* texts = nullptr) : out_(out), texts_(texts) {}
  Line(const Line&) = delete;
  Line& operator=(const Line&) = delete;
  void put(char c) {
    room(1);
    buf_[n_++] = c;
  }
  void put(std::string_view s) {
    room(s.size());
    if (s.size() > sizeof buf_) {  // room() flushed the buffer
      out_.append(s);
      return;
    }
    std::memcpy(buf_ + n_, s.data(), s.size());
    n_ += s.size();
  }
  void put_float(float f) {
    room(32);
    char* const end =
        texts_ ? texts_->put(buf_ + n_, f) : std::to_chars(buf_ + n_, buf_ + sizeof buf_, f).ptr;
    n_ = static_cast<std::size_t>(end - buf_);
  }
  // A number as append_number writes it.
  void put_number(const Numbers& x, std::size_t i) {
    if (x.precision == Precision::kFloat32) return put_float(x.f32[i]);
    flush();
    append_number(out_, x, i);
  }
  void flush() {
    out_.append(buf_, n_);
    n_ = 0;
  }
  // Room for k characters (k at most 256) written at the returned pointer, then advance(their end).
  char* reserve(std::size_t k) {
    room(k);
    return buf_ + n_;
  }
  void advance(char* end) { n_ = static_cast<std::size_t>(end - buf_); }

 private:
  void room(std::size_t k) {
    if (n_ + k > sizeof buf_) flush();
  }
  std::string& out_;
  FloatTexts* texts_;
  char buf_[256];
  std::size_t n_ = 0;
};

// The `v` lines of vertices [begin, end).
void vertex_lines(std::string& out, const Mesh& m, std::size_t begin, std::size_t end, FloatTexts* texts) {
  const std::size_t c = m.vertex_color_components;
  Line line(out, texts);
  for (std::size_t v = begin; v < end; ++v) {
    line.put("v ");
    line.put_number(m.positions, 3 * v);
    line.put(' ');
    line.put_number(m.positions, 3 * v + 1);
    line.put(' ');
    line.put_number(m.positions, 3 * v + 2);
    if (!m.vertex_weights.empty()) {
      line.put(' ');
      line.put_number(m.vertex_weights, v);
    }
    for (std::size_t k = 0; k < c && !m.vertex_colors.empty(); ++k) {
      line.put(' ');
      line.put_number(m.vertex_colors, c * v + k);
    }
    line.put('\n');
  }
  line.flush();
}

// Lines of vertices [begin, end) through `lines`, the second half on a second thread from
// kSplitFrom vertices: the shortest number text is a quarter of decompressing a large mesh. Below, the
// second thread's fresh pages and copy cost what it saves (mh_base, 19k vertices: 4% slower with the
// face lines and half the vertex lines beside). The text is the same either way (a test compares it
// with one thread's).
template <class Lines>
void split_lines(std::string& out, std::size_t begin, std::size_t end, FloatTexts* texts, Lines lines) {
  constexpr std::size_t kSplitFrom = 1 << 16;
  const std::size_t half = begin + (end - begin) / 2;
  auto second = beside(end - begin >= kSplitFrom, [&lines, half, end] {
    std::string t;
    t.reserve((end - half) * 40);
    FloatTexts own(3 * (end - half));
    lines(t, half, end, &own);
    return t;
  });
  lines(out, begin, half, texts);
  out += second.get();
}

// The `vt` or `vn` lines of values [begin, end) of `values` (`components` numbers each).
void value_lines(std::string& out, const char* keyword, const Numbers& values, std::size_t components,
                 std::size_t begin, std::size_t end, FloatTexts* texts) {
  Line line(out, texts);
  for (std::size_t i = begin; i < end; ++i) {
    line.put(keyword);
    for (std::size_t k = 0; k < components; ++k) {
      line.put(' ');
      line.put_number(values, i * components + k);
    }
    line.put('\n');
  }
  line.flush();
}

// A corner's text at most: " v/t/n", each index up to 10 digits.
constexpr std::size_t kCornerText = 1 + 3 * 10 + 2;

// One OBJ index (0-based i written 1-based) at `to`; returns its end.
char* put_index(char* to, std::uint32_t i) { return std::to_chars(to, to + 10, std::uint64_t{i} + 1).ptr; }

// One room check a corner, not one a word: face lines were a twelfth of decompressing a quad mesh.
void face_line(Line& line, const Mesh& m, std::size_t f) {
  line.put('f');
  for (std::uint32_t c = m.face_offsets[f]; c < m.face_offsets[f + 1]; ++c) {
    char* p = line.reserve(kCornerText);
    *p++ = ' ';
    p = put_index(p, m.corner_vertices[c]);
    const std::uint32_t t = m.corner_texcoords.empty() ? kInvalid : m.corner_texcoords[c];
    const std::uint32_t n = m.corner_normals.empty() ? kInvalid : m.corner_normals[c];
    if (t != kInvalid || n != kInvalid) {
      *p++ = '/';
      if (t != kInvalid) p = put_index(p, t);
      if (n != kInvalid) {
        *p++ = '/';
        p = put_index(p, n);
      }
    }
    line.advance(p);
  }
  line.put('\n');
}

constexpr const char* kLabelKeyword[4] = {"o", "g", "usemtl", "s"};

const FaceLabels& labels(const Mesh& m, int k) {
  return k == 0 ? m.objects : k == 1 ? m.groups : k == 2 ? m.materials : m.smoothing;
}

// Ends a line of text kept from the file. Text ending in a backslash would join the next line: an
// empty comment follows it, so the backslash no longer ends the line. (An empty line after it, as
// before, lost a lone backslash kept from a backslash and a comment: joined to the empty line, it
// read as a blank line; fuzz_read_mesh.)
void end_text_line(std::string& out) { out += out.ends_with('\\') ? " #\n" : "\n"; }

// "keyword text", or the keyword alone for an empty text.
void keyword_line(std::string& out, const char* keyword, const std::string& text) {
  out += keyword;
  if (!text.empty()) {
    out += ' ';
    out += text;
  }
  end_text_line(out);
}

void label_line(std::string& out, int kind, const std::string& name) {
  keyword_line(out, kLabelKeyword[kind], name);
}

void tag_line(std::string& out, const Tag& t) {
  out += "t ";
  out += t.name;
  out += ' ';
  append_uint(out, t.ints.size());
  out += '/';
  append_uint(out, t.floats.size());
  out += '/';
  append_uint(out, t.strings.size());
  for (const std::int64_t i : t.ints) {
    out += ' ';
    out += std::to_string(i);
  }
  for (std::size_t i = 0; i < t.floats.size(); ++i) {
    out += ' ';
    append_number(out, t.floats, i);
  }
  for (const std::string& s : t.strings) {
    out += ' ';
    out += s;
  }
  out += '\n';
}

void refuse_for_obj(const Mesh& m) {
  Refusal r("OBJ");
  r.add(m.face_color_components ? m.face_count() : 0, "face colours", "color");
  r.add(m.vertex_properties.size() + m.face_properties.size(), "PLY properties", "extra");
  r.add(m.ply.obj_info.size(), "PLY obj_info lines", "extra");
  if (!m.vertex_weights.empty() && !m.vertex_colors.empty())
    r.add(m.vertex_count(), "vertices with both a weight and a colour", "extra");
  r.throw_if_any();
}

// The order the canonical writer writes the faces in: as they are, unless a face without a label of
// some kind comes after one with a label of that kind, which OBJ cannot say (no statement takes a
// label away); then the faces with fewer labels first, else in order. A file's faces without a label
// of a kind are a prefix of its faces, so those prefixes are nested and this puts each first again.
std::vector<std::uint32_t> face_write_order(const Mesh& m) {
  const auto nf = static_cast<std::uint32_t>(m.face_count());
  std::vector<std::uint32_t> order(nf), missing(nf, 0);
  bool sort = false;
  for (int k = 0; k < 4; ++k) {
    const FaceLabels& l = labels(m, k);
    bool labelled = false;
    for (std::uint32_t f = 0; f < l.face.size(); ++f) {
      if (l.face[f] != kInvalid)
        labelled = true;
      else
        ++missing[f], sort = sort || labelled;
    }
  }
  for (std::uint32_t f = 0; f < nf; ++f) order[f] = f;
  if (sort)
    std::stable_sort(order.begin(), order.end(),
                     [&missing](std::uint32_t a, std::uint32_t b) { return missing[a] > missing[b]; });
  return order;
}

// The faces in `order` with their label statements where a label changes (canonical order), then the
// names no face takes.
void faces_with_labels(std::string& out, const Mesh& m, std::span<const std::uint32_t> order) {
  std::uint32_t current[4] = {kInvalid, kInvalid, kInvalid, kInvalid};
  Line line(out);
  for (const std::uint32_t f : order) {
    for (int k = 0; k < 4; ++k) {
      const FaceLabels& l = labels(m, k);
      if (l.face.empty() || l.face[f] == current[k]) continue;
      if (l.face[f] == kInvalid) {
        throw Error(ErrorCode::kUnsupported,
                    "OBJ cannot hold face " + std::to_string(f) + ": it has no `" + kLabelKeyword[k] +
                        "` after faces with one (keep the file's order, or drop them)");
      }
      current[k] = l.face[f];
      line.flush();
      label_line(out, k, l.names[current[k]]);
    }
    face_line(line, m, f);
  }
  line.flush();
  // Names no face takes (a `g` no face follows) after the faces, where such a statement stands.
  for (int k = 0; k < 4; ++k) {
    const FaceLabels& l = labels(m, k);
    std::vector<bool> taken(l.names.size(), false);
    for (const std::uint32_t n : l.face)
      if (n != kInvalid) taken[n] = true;
    for (std::size_t n = 0; n < l.names.size(); ++n)
      if (!taken[n]) label_line(out, k, l.names[n]);
  }
}

// How many vertex, UV and normal numbers a mesh has (a FloatTexts' size).
std::size_t number_count(const Mesh& m) { return m.positions.size() + m.texcoords.size() + m.normals.size(); }

// OBJ in the file's statement order; label statements must match the per-face labels.
void obj_in_order(std::string& out, const Mesh& m) {
  std::size_t v = 0, t = 0, n = 0, f = 0, lib = 0, tag = 0, comment = 0, text = 0;
  FloatTexts texts(number_count(m));
  std::uint32_t current[4] = {kInvalid, kInvalid, kInvalid, kInvalid};
  for (const Statement& s : m.statements) {
    switch (s.kind) {
      case ObjStatement::kVertex:
        split_lines(out, v, v + s.value, &texts,
                    [&m](std::string& o, std::size_t b, std::size_t e, FloatTexts* ts) {
                      vertex_lines(o, m, b, e, ts);
                    });
        v += s.value;
        break;
      case ObjStatement::kTexcoord:
        value_lines(out, "vt", m.texcoords, m.texcoord_components, t, t + s.value, &texts);
        t += s.value;
        break;
      case ObjStatement::kNormal:
        value_lines(out, "vn", m.normals, 3, n, n + s.value, &texts);
        n += s.value;
        break;
      case ObjStatement::kFace: {
        Line line(out);
        for (std::uint32_t i = 0; i < s.value; ++i, ++f) {
          for (int k = 0; k < 4; ++k) {
            const FaceLabels& l = labels(m, k);
            if (!l.face.empty() && l.face[f] != current[k]) {
              throw Error(ErrorCode::kUsage, "the mesh's statement order does not match face " +
                                                 std::to_string(f) + "'s `" + kLabelKeyword[k] +
                                                 "`; clear Mesh::statements to write the canonical order");
            }
          }
          face_line(line, m, f);
        }
        line.flush();
        break;
      }
      case ObjStatement::kObject:
      case ObjStatement::kGroup:
      case ObjStatement::kMaterial:
      case ObjStatement::kSmoothing: {
        const int k = static_cast<int>(s.kind) - static_cast<int>(ObjStatement::kObject);
        current[k] = s.value;
        label_line(out, k, labels(m, k).names[s.value]);
        break;
      }
      case ObjStatement::kMaterialLibrary:
        for (std::uint32_t i = 0; i < s.value; ++i) keyword_line(out, "mtllib", m.material_libraries[lib++]);
        break;
      case ObjStatement::kTag:
        for (std::uint32_t i = 0; i < s.value; ++i) tag_line(out, m.tags[tag++]);
        break;
      case ObjStatement::kComment:
        for (std::uint32_t i = 0; i < s.value; ++i) (out += '#') += m.comments[comment++] + '\n';
        break;
      case ObjStatement::kVerbatim:
        for (std::uint32_t i = 0; i < s.value; ++i) {
          out += m.verbatim[text++];
          end_text_line(out);
        }
        break;
    }
  }
}

void obj_canonical(std::string& out, const Mesh& m) {
  for (const std::string& c : m.comments) (out += '#') += c + '\n';
  for (const std::string& l : m.material_libraries) keyword_line(out, "mtllib", l);
  for (const std::string& t : m.verbatim) {
    out += t;
    end_text_line(out);
  }
  FloatTexts texts(number_count(m));
  split_lines(
      out, 0, m.vertex_count(), &texts,
      [&m](std::string& o, std::size_t b, std::size_t e, FloatTexts* ts) { vertex_lines(o, m, b, e, ts); });
  value_lines(out, "vt", m.texcoords, m.texcoord_components, 0, m.texcoords.size() / m.texcoord_components,
              &texts);
  value_lines(out, "vn", m.normals, 3, 0, m.normals.size() / 3, &texts);
  const std::vector<std::uint32_t> order = face_write_order(m);
  faces_with_labels(out, m, order);
  // A face index (hole) names the face where it is written.
  std::vector<std::uint32_t> written(order.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) written[order[i]] = i;
  for (const Tag& t : m.tags) {
    if (tag_indices(t.name) != TagIndices::kFaces) {
      tag_line(out, t);
      continue;
    }
    Tag moved = t;
    for (std::int64_t& f : moved.ints)
      if (f >= 0 && static_cast<std::uint64_t>(f) < written.size()) f = written[static_cast<std::size_t>(f)];
    tag_line(out, moved);
  }
}

std::size_t expected_size(const Mesh& m) {
  return m.positions.size() * 10 + m.corner_count() * 8 + m.texcoords.size() * 10 + m.normals.size() * 10 +
         64;
}

// ----------------------------------------------------------------------------------------------
// PLY

// The PLY types' sizes, in ScalarType order.
constexpr int kTypeSize[] = {1, 1, 2, 2, 4, 4, 4, 8};
bool is_float(ScalarType t) { return t == ScalarType::kFloat32 || t == ScalarType::kFloat64; }

// The narrowest PLY type that holds every value of `n` exactly, among integers when all are integers
// in [0, 255] (colours), else float or double.
ScalarType natural_type(const Numbers& n, bool integer_colors) {
  if (integer_colors) {
    // Bytes, unless every value is 0 or 1: float colours of white and black, which as bytes would read as
    // near black.
    bool bytes = true, above_one = false;
    for (std::size_t i = 0; i < n.size() && bytes; ++i) {
      const double v = n.approx(i);
      bytes = v >= 0 && v <= 255 && v == std::floor(v);
      above_one = above_one || v > 1;
    }
    if (bytes && above_one) return ScalarType::kUint8;
  }
  return n.precision == Precision::kFloat32 ? ScalarType::kFloat32 : ScalarType::kFloat64;
}

// A field as written: its numbers and where value e of the element is in them.
struct Column {
  const Numbers* values = nullptr;
  std::size_t stride = 1, offset = 0;  // value e is values[stride * e + offset]
  const Property* list = nullptr;      // a list property
  bool corners = false;                // the face's vertex indices
};

struct Field {
  PlyField field;
  Column column;
};

class PlyWriter {
 public:
  PlyWriter(const Mesh& m, PlyFormat format) : m_(m), format_(format) {}

  std::string write() {
    refuse();
    lay_out();
    std::string out = "ply\nformat ";
    out += format_ == PlyFormat::kAscii                ? "ascii"
           : format_ == PlyFormat::kBinaryLittleEndian ? "binary_little_endian"
                                                       : "binary_big_endian";
    out += " 1.0\n";
    for (const std::string& c : m_.comments) keyword_line(out, "comment", c);
    for (const std::string& c : m_.ply.obj_info) keyword_line(out, "obj_info", c);
    const bool faces = !m_.face_offsets.empty() && (m_.face_count() > 0 || !m_.ply.face.empty());
    const auto element = [&](bool vertex) {
      out += vertex ? "element vertex " : "element face ";
      append_uint(out, vertex ? m_.vertex_count() : m_.face_count());
      out += '\n';
      for (const Field& f : vertex ? vertex_ : face_) {
        out += "property ";
        if (f.column.list || f.column.corners) {
          out += "list ";
          out += scalar_type_name(f.field.count_type);
          out += ' ';
        }
        out += scalar_type_name(f.field.type);
        out += ' ';
        out += f.field.name;
        out += '\n';
      }
    };
    const bool faces_first = m_.ply.faces_first && faces;
    if (faces_first) element(false);
    element(true);
    if (faces && !faces_first) element(false);
    out += "end_header\n";
    const auto data = [&](bool vertex) {
      const std::size_t count = vertex ? m_.vertex_count() : m_.face_count();
      for (std::size_t e = 0; e < count; ++e) row(out, vertex ? vertex_ : face_, e);
    };
    if (faces_first) data(false);
    data(true);
    if (faces && !faces_first) data(false);
    return out;
  }

 private:
  void refuse() const {
    Refusal r("PLY");
    refuse_what_off_and_ply_lack(r, m_);
    // A lone `red` would read back as an unknown property, not a colour.
    if (m_.face_color_components == 1)
      r.add(m_.face_colors.size(), "face colour-map indices (OFF's one-number face colours)", "color");
    r.throw_if_any();
  }

  // The file's own fields where their data is there, then fields for data it had no field for.
  void lay_out() {
    bool position[3] = {}, normal[3] = {}, texcoord[2] = {}, color[4] = {}, face_color[4] = {};
    bool corners = false;
    std::vector<bool> vprop(m_.vertex_properties.size()), fprop(m_.face_properties.size());
    for (const PlyField& f : m_.ply.vertex) {
      if (f.role == PlyRole::kPosition && f.index < 3 && !position[f.index]) {
        position[f.index] = true;
        add(vertex_, f, {&m_.positions, 3, f.index});
      } else if (f.role == PlyRole::kNormal && f.index < 3 && !m_.normals.empty() && !normal[f.index]) {
        normal[f.index] = true;
        add(vertex_, f, {&m_.normals, 3, f.index});
      } else if (f.role == PlyRole::kTexcoord && f.index < 2 && !m_.texcoords.empty() && !texcoord[f.index]) {
        texcoord[f.index] = true;
        add(vertex_, f, {&m_.texcoords, 2, f.index});
      } else if (f.role == PlyRole::kColor && f.index < m_.vertex_color_components &&
                 !m_.vertex_colors.empty() && !color[f.index]) {
        color[f.index] = true;
        add(vertex_, f, {&m_.vertex_colors, m_.vertex_color_components, f.index});
      } else if (f.role == PlyRole::kProperty && f.index < vprop.size() && !vprop[f.index]) {
        vprop[f.index] = true;
        add_property(vertex_, f, m_.vertex_properties[f.index]);
      }
    }
    for (const PlyField& f : m_.ply.face) {
      if (f.role == PlyRole::kVertexIndices && !corners) {
        corners = true;
        Field x{f, {}};
        x.column.corners = true;
        face_.push_back(x);
      } else if (f.role == PlyRole::kColor && f.index < m_.face_color_components && !m_.face_colors.empty() &&
                 !face_color[f.index]) {
        face_color[f.index] = true;
        add(face_, f, {&m_.face_colors, m_.face_color_components, f.index});
      } else if (f.role == PlyRole::kProperty && f.index < fprop.size() && !fprop[f.index]) {
        fprop[f.index] = true;
        add_property(face_, f, m_.face_properties[f.index]);
      }
    }
    static constexpr const char* kXyz[] = {"x", "y", "z"};
    static constexpr const char* kNormal[] = {"nx", "ny", "nz"};
    static constexpr const char* kUv[] = {"u", "v"};
    static constexpr const char* kSt[] = {"s", "t"};
    static constexpr const char* kRgba[] = {"red", "green", "blue", "alpha"};
    const auto fresh = [&](std::vector<Field>& to, PlyRole role, std::uint32_t k, const char* name,
                           const Numbers& n, std::size_t stride, bool colors) {
      PlyField f;
      f.role = role;
      f.index = k;
      f.name = name;
      f.type = natural_type(n, colors);
      add(to, f, {&n, stride, k});
    };
    for (std::uint32_t k = 0; k < 3; ++k) {
      if (!position[k]) fresh(vertex_, PlyRole::kPosition, k, kXyz[k], m_.positions, 3, false);
    }
    for (std::uint32_t k = 0; k < 3 && !m_.normals.empty(); ++k) {
      if (!normal[k]) fresh(vertex_, PlyRole::kNormal, k, kNormal[k], m_.normals, 3, false);
    }
    // u v, or s t where a property already has one of those names (a lone `u` is a property of its own).
    bool uv_taken = false;
    for (const Property& q : m_.vertex_properties) uv_taken = uv_taken || q.name == "u" || q.name == "v";
    for (std::uint32_t k = 0; k < 2 && !m_.texcoords.empty(); ++k) {
      if (!texcoord[k])
        fresh(vertex_, PlyRole::kTexcoord, k, (uv_taken ? kSt : kUv)[k], m_.texcoords, 2, false);
    }
    for (std::uint32_t k = 0; k < m_.vertex_color_components && !m_.vertex_colors.empty(); ++k) {
      if (!color[k])
        fresh(vertex_, PlyRole::kColor, k, kRgba[k], m_.vertex_colors, m_.vertex_color_components, true);
    }
    other_properties(vertex_, m_.vertex_properties, vprop);
    if (!corners) {
      PlyField f;
      f.role = PlyRole::kVertexIndices;
      f.name = "vertex_indices";
      std::uint32_t most = 0;
      for (std::size_t i = 0; i < m_.face_count(); ++i) most = std::max(most, m_.degree(i));
      f.count_type = most <= 255 ? ScalarType::kUint8 : ScalarType::kUint32;
      f.type = m_.vertex_count() <= 0x7FFFFFFFu ? ScalarType::kInt32 : ScalarType::kUint32;
      Field x{f, {}};
      x.column.corners = true;
      face_.insert(face_.begin(), x);
    }
    for (std::uint32_t k = 0; k < m_.face_color_components && !m_.face_colors.empty(); ++k) {
      if (!face_color[k])
        fresh(face_, PlyRole::kColor, k, kRgba[k], m_.face_colors, m_.face_color_components, true);
    }
    other_properties(face_, m_.face_properties, fprop);
    for (Field& f : face_) {
      if (!f.column.corners) continue;
      // The index type must hold every vertex, the length type every degree.
      if (!fits_unsigned(f.field.type, m_.vertex_count() == 0 ? 0 : m_.vertex_count() - 1) ||
          is_float(f.field.type))
        f.field.type = ScalarType::kUint32;
      std::uint32_t most = 0;
      for (std::size_t i = 0; i < m_.face_count(); ++i) most = std::max(most, m_.degree(i));
      if (!fits_unsigned(f.field.count_type, most) || is_float(f.field.count_type))
        f.field.count_type = ScalarType::kUint32;
    }
    // Two fields of one name would not read back (a decoded property named as a field the writer adds).
    for (const auto* fields : {&vertex_, &face_})
      for (std::size_t i = 0; i < fields->size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
          if ((*fields)[i].field.name == (*fields)[j].field.name)
            throw Error(ErrorCode::kUsage, std::string("PLY cannot hold two ") +
                                               (fields == &vertex_ ? "vertex" : "face") +
                                               " properties named '" + (*fields)[i].field.name + "'");
  }

  // Whether float32 holds every value of a column (a float32 field of a file whose other fields are
  // float64 shares their Numbers: each value is checked, not the list's precision).
  bool float32_column(const Column& c) const {
    const Numbers& n = *c.values;
    if (n.precision == Precision::kFloat32) return true;
    const auto holds = [&n](std::size_t i) {
      if (std::isnan(n.f32[i])) return std::isnan(n.f64[i]);  // a NaN is as much a float32 as a float64
      return !detail::find_decimal(n, i) && detail::shortest_double(n.f32[i]) == n.f64[i];
    };
    if (c.list) {
      for (std::size_t i = 0; i < n.size(); ++i) {
        if (!holds(i)) return false;
      }
      return true;
    }
    for (std::size_t i = c.offset; i < n.size(); i += c.stride) {
      if (!holds(i)) return false;
    }
    return true;
  }

  // The properties the file's layout had no field for, at the end.
  void other_properties(std::vector<Field>& to, const std::vector<Property>& props,
                        const std::vector<bool>& laid_out) {
    for (std::size_t i = 0; i < props.size(); ++i) {
      if (laid_out[i]) continue;
      PlyField f;
      f.index = static_cast<std::uint32_t>(i);
      f.name = props[i].name;
      f.type = props[i].type;
      f.count_type = props[i].count_type;
      add_property(to, f, props[i]);
    }
  }

  static bool fits_unsigned(ScalarType t, std::uint64_t v) {
    switch (t) {
      case ScalarType::kInt8:
        return v <= 127;
      case ScalarType::kUint8:
        return v <= 255;
      case ScalarType::kInt16:
        return v <= 32767;
      case ScalarType::kUint16:
        return v <= 65535;
      case ScalarType::kInt32:
        return v <= 0x7FFFFFFFu;
      case ScalarType::kUint32:
        return v <= 0xFFFFFFFFu;
      default:
        return true;
    }
  }

  // A field of `numbers`, its float type widened where the values need float64 (binary); integer
  // types must hold every value.
  void add(std::vector<Field>& to, PlyField f, Column c) {
    if (f.type == ScalarType::kFloat32 && format_ != PlyFormat::kAscii && !float32_column(c))
      f.type = ScalarType::kFloat64;
    if (c.values->precision == Precision::kDecimal && format_ != PlyFormat::kAscii) {
      throw Error(ErrorCode::kUnsupported,
                  "binary PLY cannot hold '" + f.name +
                      "': it has decimals no float64 holds (more than 17 significant "
                      "digits); write ASCII PLY or OBJ");
    }
    if (!is_float(f.type)) check_integers(f, c);
    to.push_back({std::move(f), c});
  }

  void add_property(std::vector<Field>& to, PlyField f, const Property& p) {
    Column c;
    c.values = &p.values;
    if (p.list) c.list = &p;
    f.role = PlyRole::kProperty;
    if (p.list) {
      std::uint32_t most = 0;
      for (std::size_t i = 0; i + 1 < p.offsets.size(); ++i)
        most = std::max(most, p.offsets[i + 1] - p.offsets[i]);
      if (!fits_unsigned(f.count_type, most) || is_float(f.count_type)) f.count_type = ScalarType::kUint32;
    }
    add(to, std::move(f), c);
  }

  // Only the column's own values: x of positions is every third number (a fuzzed PLY with an int x and
  // float y, z was refused on y's fractions).
  static void check_integers(const PlyField& f, const Column& c) {
    static constexpr double kLo[] = {-128, 0, -32768, 0, -2147483648.0, 0};
    static constexpr double kHi[] = {127, 255, 32767, 65535, 2147483647.0, 4294967295.0};
    const auto t = static_cast<std::size_t>(f.type);
    const Numbers& n = *c.values;
    for (std::size_t i = c.offset; i < n.size(); i += c.stride) {
      const double v = n.approx(i);
      if (v != std::floor(v) || v < kLo[t] || v > kHi[t] || detail::find_decimal(n, i)) {
        throw Error(ErrorCode::kUsage, "PLY property '" + f.name + "' has a value its type " +
                                           std::string(scalar_type_name(f.type)) + " cannot hold");
      }
    }
  }

  void row(std::string& out, const std::vector<Field>& fields, std::size_t e) {
    bool first = true;
    for (const Field& f : fields) {
      if (f.column.corners) {
        const std::uint32_t b = m_.face_offsets[e], end = m_.face_offsets[e + 1];
        integer(out, f.field.count_type, end - b, first);
        for (std::uint32_t c = b; c < end; ++c) integer(out, f.field.type, m_.corner_vertices[c], first);
      } else if (f.column.list) {
        const Property& p = *f.column.list;
        integer(out, f.field.count_type, p.offsets[e + 1] - p.offsets[e], first);
        for (std::uint32_t i = p.offsets[e]; i < p.offsets[e + 1]; ++i)
          value(out, f.field.type, p.values, i, first);
      } else {
        value(out, f.field.type, *f.column.values, f.column.stride * e + f.column.offset, first);
      }
    }
    if (format_ == PlyFormat::kAscii) out += '\n';
  }

  void separator(std::string& out, bool& first) const {
    if (format_ == PlyFormat::kAscii && !first) out += ' ';
    first = false;
  }

  void bytes(std::string& out, std::uint64_t bits, int size) const {
    for (int i = 0; i < size; ++i) {
      const int shift = format_ == PlyFormat::kBinaryLittleEndian ? 8 * i : 8 * (size - 1 - i);
      out += static_cast<char>((bits >> shift) & 0xFF);
    }
  }

  void integer(std::string& out, ScalarType t, std::int64_t v, bool& first) const {
    separator(out, first);
    if (format_ == PlyFormat::kAscii) {
      out += std::to_string(v);
    } else {
      bytes(out, static_cast<std::uint64_t>(v), kTypeSize[static_cast<int>(t)]);
    }
  }

  void value(std::string& out, ScalarType t, const Numbers& n, std::size_t i, bool& first) const {
    if (!is_float(t)) return integer(out, t, static_cast<std::int64_t>(n.approx(i)), first);
    separator(out, first);
    if (format_ == PlyFormat::kAscii) return append_number(out, n, i);
    if (t == ScalarType::kFloat32) return bytes(out, std::bit_cast<std::uint32_t>(n.f32[i]), 4);
    bytes(out, std::bit_cast<std::uint64_t>(detail::exact_double(n, i)), 8);
  }

  const Mesh& m_;
  PlyFormat format_;
  std::vector<Field> vertex_, face_;
};

}  // namespace

std::string write_obj_mesh(const Mesh& m, const WriteOptions& options) {
  detail::check_mesh_arrays(m);
  refuse_for_obj(m);
  std::string out;
  out.reserve(expected_size(m));
  if (options.keep_order && !m.statements.empty()) {
    obj_in_order(out, m);
  } else {
    obj_canonical(out, m);
  }
  // A kept line that starts with a byte order mark, first in the file: readers take a leading one for
  // a mark, not content, so one more goes in front (fuzz_read_mesh).
  if (out.starts_with("\xEF\xBB\xBF")) out.insert(0, "\xEF\xBB\xBF");
  return out;
}

std::string write_off_mesh(const Mesh& m) {
  detail::check_mesh_arrays(m);
  Refusal r("OFF");
  refuse_what_off_and_ply_lack(r, m);
  r.add(m.vertex_properties.size() + m.face_properties.size(), "PLY properties", "extra");
  r.add(m.ply.obj_info.size(), "PLY obj_info lines", "extra");
  r.throw_if_any();
  const bool uv = !m.texcoords.empty();
  std::string out;
  out.reserve(expected_size(m));
  if (uv) out += "ST";
  if (!m.vertex_colors.empty()) out += 'C';
  if (!m.normals.empty()) out += 'N';
  out += "OFF\n";
  // After the header line: readers recognise OFF by its first line.
  for (const std::string& c : m.comments) (out += '#') += c + '\n';
  append_uint(out, m.vertex_count());
  out += ' ';
  append_uint(out, m.face_count());
  out += " 0\n";
  FloatTexts texts(number_count(m));
  split_lines(out, 0, m.vertex_count(), &texts,
              [&m, uv](std::string& o, std::size_t b, std::size_t e, FloatTexts* ts) {
                const std::size_t c = m.vertex_color_components;
                Line line(o, ts);
                const auto numbers = [&line](const Numbers& x, std::size_t from, std::size_t count) {
                  for (std::size_t k = 0; k < count; ++k) {
                    if (k) line.put(' ');
                    line.put_number(x, from + k);
                  }
                };
                for (std::size_t v = b; v < e; ++v) {
                  numbers(m.positions, 3 * v, 3);
                  if (!m.normals.empty()) line.put(' '), numbers(m.normals, 3 * v, 3);
                  if (!m.vertex_colors.empty()) line.put(' '), numbers(m.vertex_colors, c * v, c);
                  if (uv) line.put(' '), numbers(m.texcoords, 2 * v, 2);
                  line.put('\n');
                }
                line.flush();
              });
  const std::size_t fc = m.face_color_components;
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    append_uint(out, m.degree(f));
    for (std::uint32_t c = m.face_offsets[f]; c < m.face_offsets[f + 1]; ++c) {
      out += ' ';
      append_uint(out, m.corner_vertices[c]);
    }
    for (std::size_t k = 0; k < fc && !m.face_colors.empty(); ++k)
      (out += ' '), append_number(out, m.face_colors, fc * f + k);
    out += '\n';
  }
  return out;
}

std::string write_ply_mesh(const Mesh& m, const WriteOptions& options) {
  detail::check_mesh_arrays(m);
  const bool own = options.ply_keep_format && !m.ply.vertex.empty();
  return PlyWriter(m, own ? m.ply.format : options.ply_format).write();
}

std::string write_mesh(const Mesh& m, MeshFormat format, const WriteOptions& options) {
  switch (format) {
    case MeshFormat::kObj:
      return write_obj_mesh(m, options);
    case MeshFormat::kOff:
      return write_off_mesh(m);
    case MeshFormat::kPly:
      return write_ply_mesh(m, options);
    default:
      break;
  }
  throw Error(ErrorCode::kUsage, "write_mesh: not a mesh format (expected obj, off or ply)");
}

}  // namespace qsp
