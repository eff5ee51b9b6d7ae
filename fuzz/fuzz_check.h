// What every fuzz target asserts. A violated property aborts with a message libFuzzer reports as a
// crash, so `tools/hardening.sh` fails and the input is saved.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"

namespace qsp::fuzz {

[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "\nqsp fuzz finding: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

// An Error that reached the caller must be typed, say something, and never be an internal one
// (kInternal is a qsp bug by definition, see qsp/error.h).
inline void check_error(const Error& e, const char* stage) {
  if (e.code() == ErrorCode::kInternal) finding(std::string(stage) + ": internal error: " + e.what());
  if (std::strlen(e.what()) < 8) finding(std::string(stage) + ": uninformative message '" + e.what() + "'");
  const auto c = static_cast<unsigned>(e.code());
  if (c < 1 || c > 14) finding(std::string(stage) + ": error code out of range");
}

// What a reader promises about a mesh it returns.
inline void check_reader_output(const QuadMesh& m, const ReadReport& report, const char* stage) {
  if (m.positions.size() % 3 != 0 || m.quads.size() % 4 != 0)
    finding(std::string(stage) + ": partial element");
  for (float x : m.positions) {
    if (!std::isfinite(x)) finding(std::string(stage) + ": returned a non-finite coordinate");
  }
  const std::size_t nv = m.vertex_count();
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    for (int i = 0; i < 4; ++i) {
      if (m.quads[4 * f + i] >= nv) finding(std::string(stage) + ": returned an index out of range");
      for (int j = 0; j < i; ++j) {
        if (m.quads[4 * f + i] == m.quads[4 * f + j])
          finding(std::string(stage) + ": returned a degenerate face");
      }
    }
  }
  if (!report.face_line.empty() && report.face_line.size() != m.face_count()) {
    finding(std::string(stage) + ": face_line has the wrong size");
  }
}

inline bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), 4 * a.size()) == 0);
}

// Codes that build_adjacency / encode may legitimately refuse a reader-accepted mesh with.
inline bool invalid_mesh_code(ErrorCode c) {
  return c == ErrorCode::kBadIndex || c == ErrorCode::kDegenerateFace || c == ErrorCode::kNonManifold ||
         c == ErrorCode::kOrientation || c == ErrorCode::kLimit;
}

// build_adjacency on a reader-accepted mesh: accepts it, or refuses it with an invalid-mesh code.
inline void check_adjacency(const QuadMesh& mesh) {
  try {
    (void)build_adjacency(mesh);
  } catch (const Error& e) {
    check_error(e, "build_adjacency");
    if (!invalid_mesh_code(e.code())) finding(std::string("build_adjacency: unexpected code: ") + e.what());
  }
}

// A text reader's target (OBJ, OFF): only typed errors; an accepted mesh is sane, writes back to text
// that reads to the same mesh bit for bit, and build_adjacency refuses it cleanly or not at all.
// `name` is the format's extension ("obj"), naming the stages in findings.
template <class Read, class Write>
void check_text_reader(std::string_view text, const std::string& name, Read read, Write write) {
  const std::string reader = "read_" + name, writer = "write_" + name;
  ReadReport report;
  QuadMesh mesh;
  try {
    mesh = read(text, "fuzz." + name, &report);
  } catch (const Error& e) {
    check_error(e, reader.c_str());
    return;
  }
  check_reader_output(mesh, report, reader.c_str());
  try {
    const std::string again = write(mesh);
    QuadMesh back = read(again, "rewritten." + name, nullptr);
    if (back.quads != mesh.quads || !same_bits(back.positions, mesh.positions)) {
      finding(reader + "(" + writer + "(m)) != m");
    }
  } catch (const Error& e) {
    finding(writer + "/" + reader + " of an accepted mesh failed: " + e.what());
  }
  check_adjacency(mesh);
}

// The round-trip property: a valid mesh compresses, and decompresses to a mesh isomorphic to it
// (orientation included) with bit-identical positions; the canonical bytes are a fixed point; with
// keep-order the exact face list comes back. Returns false if the mesh is refused (a typed invalid-
// mesh error), aborts on any violation.
inline bool check_round_trip(const QuadMesh& mesh, const char* stage) {
  OrderMap order;
  std::string bytes;
  try {
    bytes = encode(mesh, {}, &order);
  } catch (const Error& e) {
    check_error(e, stage);
    if (!invalid_mesh_code(e.code()))
      finding(std::string(stage) + ": encode refused with an unexpected code: " + e.what());
    return false;
  }
  const std::string s = stage;
  QuadMesh d;
  try {
    d = decode(bytes);
  } catch (const Error& e) {
    finding(s + ": decode refused what encode wrote: " + e.what());
  }
  const std::size_t nv = mesh.vertex_count(), nf = mesh.face_count();
  if (d.vertex_count() != nv || d.face_count() != nf) finding(s + ": decoded counts differ");
  if (order.vertex.size() != nv || order.face.size() != nf || order.rotation.size() != nf)
    finding(s + ": order map size");
  std::vector<std::uint8_t> seen(nv, 0);
  for (std::uint32_t v : order.vertex) {
    if (v >= nv || seen[v]) finding(s + ": vertex map is not a permutation");
    seen[v] = 1;
  }
  seen.assign(nf, 0);
  for (std::uint32_t f : order.face) {
    if (f >= nf || seen[f]) finding(s + ": face map is not a permutation");
    seen[f] = 1;
  }
  for (std::size_t f = 0; f < nf; ++f) {
    const std::uint32_t cf = order.face[f], r = order.rotation[f] & 3u;
    for (std::uint32_t c = 0; c < 4; ++c) {
      if (d.quads[4 * std::size_t{cf} + c] != order.vertex[mesh.quads[4 * f + (c + r) % 4]]) {
        finding(s + ": decoded face " + std::to_string(cf) + " is not input face " + std::to_string(f));
      }
    }
  }
  for (std::size_t v = 0; v < nv; ++v) {
    if (std::memcmp(&d.positions[3 * std::size_t{order.vertex[v]}], &mesh.positions[3 * v], 12) != 0) {
      finding(s + ": position of vertex " + std::to_string(v) + " changed");
    }
  }
  // Canonical form: the decoded mesh encodes to the same bytes.
  try {
    if (encode(d) != bytes) finding(s + ": re-encoding the decoded mesh gives different bytes");
  } catch (const Error& e) {
    finding(s + ": re-encoding the decoded mesh failed: " + e.what());
  }
  // Keep-order gives back the identical face list and positions.
  try {
    EncodeOptions keep;
    keep.keep_order = true;
    keep.partition = PartitionMode::kMotorcycle;  // the order section does not depend on the partition
    QuadMesh k = decode(encode(mesh, keep));
    if (k.quads != mesh.quads || !same_bits(k.positions, mesh.positions))
      finding(s + ": --keep-order changed the mesh");
    FileInfo info = inspect(bytes);
    if (info.vertices != nv || info.faces != nf || info.total_bytes != bytes.size())
      finding(s + ": inspect disagrees");
  } catch (const Error& e) {
    finding(s + ": keep-order or inspect failed: " + e.what());
  }
  return true;
}

}  // namespace qsp::fuzz
