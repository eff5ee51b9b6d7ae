// The statement order section (format 3.11, optional; format-spec/qsp_format.md, "Statement order
// section"): the OBJ file's statements in its order, so that --keep-order gives back the same statements
// in the same places, not only the same arrays.
#include <array>
#include <string>
#include <vector>

#include "bytes.h"
#include "codec_sections.h"
#include "qsp/error.h"

namespace qsp {
namespace {

constexpr const char* kSection = "statement order section";
constexpr std::uint8_t kKinds = 12;

bool is_label(ObjStatement k) { return k >= ObjStatement::kObject && k <= ObjStatement::kSmoothing; }
int label_kind(ObjStatement k) { return static_cast<int>(k) - static_cast<int>(ObjStatement::kObject); }
const FaceLabels& labels_of(const PolygonMesh& m, int k) {
  return k == 0 ? m.objects : k == 1 ? m.groups : k == 2 ? m.materials : m.smoothing;
}

[[noreturn]] void fail(const std::string& what, std::uint64_t offset) {
  throw Error(ErrorCode::kFormat,
              std::string(kSection) + ": " + what + " (at byte offset " + std::to_string(offset) + ")");
}

// Appends a run of `n` statements of `kind`, joined to a run of the same kind before it.
void add_run(std::vector<Statement>& st, ObjStatement kind, std::size_t n) {
  if (n == 0) return;
  if (!st.empty() && st.back().kind == kind) {
    st.back().value += static_cast<std::uint32_t>(n);
  } else {
    st.push_back({kind, static_cast<std::uint32_t>(n)});
  }
}

}  // namespace

bool statements_needed(const PolygonMesh& m) {
  if (m.statements.empty()) return false;
  // The canonical writer (io_write.cpp) moves faces without a label of a kind before faces with one;
  // where the file had them elsewhere, its order differs.
  for (int k = 0; k < 4; ++k) {
    const FaceLabels& l = labels_of(m, k);
    bool labelled = false;
    for (const std::uint32_t name : l.face) {
      if (name == kInvalid && labelled) return true;
      labelled = labelled || name != kInvalid;
    }
  }
  // What it writes: libraries, kept lines, v, vt, vn, each face after the label statements that change
  // before it (o, g, usemtl, s), the names no face takes, the tags.
  std::vector<Statement> st;
  add_run(st, ObjStatement::kMaterialLibrary, m.material_libraries.size());
  add_run(st, ObjStatement::kVerbatim, m.kept_lines.size());
  add_run(st, ObjStatement::kVertex, m.vertex_count());
  add_run(st, ObjStatement::kTexcoord,
          m.texcoord_components ? m.texcoords.size() / m.texcoord_components : 0);
  add_run(st, ObjStatement::kNormal, m.normals.size() / 3);
  std::array<std::uint32_t, 4> current = {kInvalid, kInvalid, kInvalid, kInvalid};
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    for (int k = 0; k < 4; ++k) {
      const FaceLabels& l = labels_of(m, k);
      if (l.face.empty() || l.face[f] == current[static_cast<std::size_t>(k)]) continue;
      current[static_cast<std::size_t>(k)] = l.face[f];
      st.push_back({static_cast<ObjStatement>(static_cast<int>(ObjStatement::kObject) + k), l.face[f]});
    }
    add_run(st, ObjStatement::kFace, 1);
  }
  for (int k = 0; k < 4; ++k) {
    const FaceLabels& l = labels_of(m, k);
    std::vector<bool> taken(l.names.size(), false);
    for (const std::uint32_t n : l.face)
      if (n != kInvalid && n < taken.size()) taken[n] = true;
    for (std::uint32_t n = 0; n < l.names.size(); ++n)
      if (!taken[n])
        st.push_back({static_cast<ObjStatement>(static_cast<int>(ObjStatement::kObject) + k), n});
  }
  add_run(st, ObjStatement::kTag, m.tags.size());
  if (st.size() != m.statements.size()) return true;
  for (std::size_t i = 0; i < st.size(); ++i)
    if (st[i].kind != m.statements[i].kind || st[i].value != m.statements[i].value) return true;
  return false;
}

std::string encode_statements_section(const PolygonMesh& mesh, std::span<const std::uint32_t> input_face) {
  std::array<std::vector<std::uint32_t>, 4> number;
  for (int k = 0; k < 4; ++k)
    number[static_cast<std::size_t>(k)] = label_numbering(labels_of(mesh, k), input_face);
  std::string out;
  put_varint(out, mesh.statements.size());
  for (const Statement& s : mesh.statements) {
    if (s.kind == ObjStatement::kComment || static_cast<std::uint8_t>(s.kind) >= kKinds)
      throw Error(ErrorCode::kUsage, "encode: a comment run or an unknown kind among the statements");
    std::uint32_t value = s.value;
    if (is_label(s.kind)) {
      const std::vector<std::uint32_t>& n = number[static_cast<std::size_t>(label_kind(s.kind))];
      if (value >= n.size())
        throw Error(ErrorCode::kUsage, "encode: a statement names a label beyond its names");
      value = n[value];
    }
    out.push_back(static_cast<char>(s.kind));
    put_varint(out, value);
  }
  return out;
}

std::vector<Statement> decode_statements_section(std::string_view payload, std::uint64_t offset,
                                                 const PolygonMesh& mesh) {
  ByteReader in(payload, offset, kSection);
  const std::uint64_t count = in.varint("statement count");
  // Each statement takes at least two bytes (its kind and a varint).
  if (count == 0 || count > in.left() / 2) fail("statement count " + std::to_string(count), offset);
  const std::array<std::uint64_t, kKinds> total = {
      mesh.vertex_count(),
      mesh.texcoord_components ? mesh.texcoords.size() / mesh.texcoord_components : 0,
      mesh.normals.size() / 3,
      mesh.face_count(),
      0,
      0,
      0,
      0,
      mesh.material_libraries.size(),
      mesh.tags.size(),
      0,
      mesh.kept_lines.size()};
  std::array<std::uint64_t, kKinds> seen{};
  std::array<std::uint32_t, 4> current = {kInvalid, kInvalid, kInvalid, kInvalid};
  std::vector<Statement> out;
  out.reserve(static_cast<std::size_t>(count));
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::uint64_t at = in.offset();
    const std::uint8_t kind = in.u8("statement kind");
    const std::uint64_t value = in.varint("statement value");
    const auto k = static_cast<ObjStatement>(kind);
    if (kind >= kKinds || k == ObjStatement::kComment) fail("statement kind " + std::to_string(kind), at);
    if (is_label(k)) {
      const int lk = label_kind(k);
      if (value >= labels_of(mesh, lk).names.size())
        fail("a statement names label " + std::to_string(value) + " of " +
                 std::to_string(labels_of(mesh, lk).names.size()),
             at);
      current[static_cast<std::size_t>(lk)] = static_cast<std::uint32_t>(value);
    } else {
      std::uint64_t& n = seen[kind];
      if (value == 0 || value > total[kind] - n)
        fail("a run of " + std::to_string(value) + " where " + std::to_string(total[kind] - n) + " are left",
             at);
      // The faces of a run must carry the labels the statements before them set.
      for (std::uint64_t f = n; k == ObjStatement::kFace && f < n + value; ++f)
        for (int lk = 0; lk < 4; ++lk) {
          const FaceLabels& l = labels_of(mesh, lk);
          if (!l.face.empty() && l.face[static_cast<std::size_t>(f)] != current[static_cast<std::size_t>(lk)])
            fail("face " + std::to_string(f) + "'s labels differ from the statements before it", at);
        }
      n += value;
    }
    out.push_back({k, static_cast<std::uint32_t>(value)});
  }
  if (in.left() != 0) fail("bytes after the last statement", in.offset());
  for (std::uint8_t kind = 0; kind < kKinds; ++kind)
    if (seen[kind] != total[kind])
      fail("the runs of kind " + std::to_string(kind) + " hold " + std::to_string(seen[kind]) + " of " +
               std::to_string(total[kind]),
           offset);
  return out;
}

}  // namespace qsp
