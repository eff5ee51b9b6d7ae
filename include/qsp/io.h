// qsp/io.h: strict, exact mesh readers and writers (OBJ, OFF, PLY: qsp's own parsers).
// The only stage that knows about files. Uses only qsp/mesh.h.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/mesh.h"

namespace qsp {

enum class MeshFormat : std::uint8_t { kObj, kOff, kPly, kQsp, kUnknown };

// Reader limits (Error kLimit beyond them): kMaxVertices and kMaxFaces of qsp/mesh.h.

// Format from a path's extension (case-insensitive); kUnknown if none matches.
MeshFormat format_from_path(std::string_view path);

// What a reader saw besides positions and quads. qsp stores none of it yet; the CLI refuses input
// that has any unless the user asks to drop it (`--positions-only`), so nothing is lost silently.
struct ReadReport {
  std::uint64_t texcoords = 0;            // `vt` lines
  std::uint64_t normals = 0;              // `vn` lines
  std::uint64_t face_attribute_refs = 0;  // faces written v/vt, v//vn or v/vt/vn
  std::uint64_t groups = 0;               // `g` and `o` lines
  std::uint64_t materials = 0;            // `usemtl`, `mtllib` (and old `usemap`, `maplib`) lines
  std::uint64_t smoothing = 0;            // `s` lines
  std::uint64_t tags = 0;                 // OpenSubdiv `t` lines (creases, corners, ...)
  std::uint64_t vertex_colors = 0;        // colours after x y z on `v` lines, or PLY/OFF colour properties
  std::uint64_t face_colors = 0;          // OFF colour after a face's indices, PLY face colour properties
  std::uint64_t parameter_vertices = 0;   // OBJ `vp` lines
  std::uint64_t other_properties = 0;     // PLY vertex/face properties qsp does not know (one per element)
  std::vector<std::uint32_t> face_line;   // per face: 1-based line it starts on (0 if not from text)

  bool has_extra_data() const {
    return texcoords || normals || face_attribute_refs || groups || materials || smoothing || tags ||
           vertex_colors || face_colors || parameter_vertices || other_properties;
  }
  // "12 texture coordinates, 3 groups", empty if nothing extra.
  std::string describe_extra_data() const;
};

// Parse OBJ text. `source` names the input in messages ("file.obj:12: ..."). Accepts v/vt/vn face
// syntax, negative (relative) indices, comments, o/g/s/usemtl/mtllib/t lines, CRLF, trailing
// whitespace. Refuses (Error with source:line): non-quad faces (count + first examples), index 0 or
// out of range, a face repeating a vertex, malformed numbers, NaN/inf coordinates, unknown statements.
// Positions are float32 exactly as `std::from_chars` rounds the decimal text. Safe on untrusted input.
QuadMesh read_obj(std::string_view text, std::string_view source, ReadReport* report = nullptr);

// Parse OFF text (faces may span several lines; optional colours are reported). Same guarantees.
QuadMesh read_off(std::string_view text, std::string_view source, ReadReport* report = nullptr);

// Read PLY (ascii, binary_little_endian, binary_big_endian) with qsp's own reader: x, y, z of any
// numeric type (float32 kept bit for bit; float64 and integers rounded to the nearest float32, which
// is exact for integers up to 2^24; ASCII via std::from_chars) and the face vertex_indices list; other
// properties are counted in the report. As with text, a value that rounds to infinity or a nonzero
// value that rounds to zero is refused, and so is a property declared twice; ASCII integers must fit
// their declared type, and a leading '+' is read as in OBJ. Refuses like read_obj:
// non-quads (all counted), bad indices, repeated vertices, NaN/inf, truncated or trailing data,
// unsupported elements (edges, ...); messages give "file:line:" (ASCII) or "file: byte N:" (binary).
// Not OpenMesh: it silently rewrites non-manifold or degenerate input while reporting success.
QuadMesh read_ply_file(const std::string& path, ReadReport* report = nullptr);

// read_ply_file on bytes already in memory (standard input read once to detect its format); `source`
// names the input in messages. Same guarantees; safe on untrusted input.
QuadMesh read_ply(std::string_view bytes, const std::string& source, ReadReport* report = nullptr);

// Read a mesh file by extension (`-` = standard input, needs `format`). Throws Error(kIo) when the
// file cannot be read, kUnsupported for an unknown extension.
QuadMesh read_mesh_file(const std::string& path, ReadReport* report = nullptr,
                        MeshFormat format = MeshFormat::kUnknown);

// Write OBJ/OFF text. Floats use the shortest text that reads back to the same float
// (std::to_chars), so read(write(m)) == m bit for bit.
std::string write_obj(const QuadMesh& mesh);
std::string write_off(const QuadMesh& mesh);

// Read a whole file (or stdin for "-") into memory. Throws Error(kIo) with the path and reason.
std::string read_file_bytes(const std::string& path);

// Write bytes atomically: to an unnamed temporary file in the target's folder (O_TMPFILE; a named
// hidden one where unsupported), fsync, then link or rename it into place, so a process killed at
// any moment leaves no partial output. Refuses (kIo) to replace an existing file unless `overwrite`;
// "-" writes stdout; an existing device or FIFO (e.g. /dev/full) is written in place, never
// replaced. On any failure the temporary file is removed and Error(kIo) says why (e.g. "No space
// left on device").
void write_file_atomic(const std::string& path, std::string_view bytes, bool overwrite);

// Test seam: `hook` (nullptr, the default, for none) is called by write_file_atomic once the output is
// complete and flushed in its temporary file, just before it gets its name. The CLI sets it only for
// tests (QSP_TEST_STOP_BEFORE_RENAME), which stop the process there to kill it inside that window.
// Not to be changed while another thread writes.
void set_before_rename_hook(void (*hook)());

}  // namespace qsp
