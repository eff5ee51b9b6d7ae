// qsp/io.h: strict, exact mesh readers and writers (OBJ, OFF, PLY: qsp's own parsers).
// The only stage that knows about files. Uses only qsp/mesh.h and qsp/polymesh.h.
//
// Two readings of each format: into a qsp::Mesh (qsp/polymesh.h) with everything the file carries,
// exactly (read_obj_mesh, read_off_mesh, read_ply_mesh, read_mesh); and the QuadMesh readers below
// (read_obj, read_off, read_ply, read_mesh_file), positions rounded to float32 and quads only, which
// refuse other faces and count the rest by kind (ReadReport). Both are one parser per format and accept
// the same files but for the checks the QuadMesh readers skip (texture coordinate, normal and tag
// indices in range; vertices agreeing on having colours) and their faces being quads.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/mesh.h"
#include "qsp/polymesh.h"

namespace qsp {

enum class MeshFormat : std::uint8_t { kObj, kOff, kPly, kQsp, kUnknown };

// Reader limits (Error kLimit beyond them): kMaxVertices and kMaxFaces of qsp/mesh.h.

// Format from a path's extension (case-insensitive); kUnknown if none matches.
MeshFormat format_from_path(std::string_view path);

// A reader's note about input it kept but did not understand (an OBJ line kept as text).
struct ReadWarning {
  std::uint64_t line = 0;  // 1-based
  std::string message;     // without the "file:line: " prefix
};

// What a reader saw besides positions and quads. qsp stores none of it yet; the CLI refuses input
// that has any unless the user asks to drop it (`--drop LIST`, `--positions-only`), so nothing is lost
// silently. Each count belongs to the --drop category (qsp/polymesh.h) the Mesh readers file the same
// data under, so dropping by category means the same in both readings. Comment lines are not counted
// (the QuadMesh readers skip them): kCategoryComment is never reported.
// A coordinate float32 does not hold exactly, as the file has it (see ReadReport::rounded_coordinates).
struct RoundedCoordinate {
  std::uint64_t line = 0;    // 1-based text line (0: binary PLY)
  std::uint64_t vertex = 0;  // 0-based vertex index
  std::string value;         // the number as the file writes it ("0.1234567891234")
  float nearest = 0.0f;      // the float32 it was read as
};

struct ReadReport {
  std::uint64_t texcoords = 0;             // uv: `vt` lines; per-vertex u/v (PLY) or ST (OFF)
  std::uint64_t faces_with_texcoords = 0;  // uv: faces written v/vt or v/vt/vn
  std::uint64_t normals = 0;               // normal: `vn` lines; per-vertex nx/ny/nz (PLY) or N (OFF)
  std::uint64_t faces_with_normals = 0;    // normal: faces written v//vn or v/vt/vn
  std::uint64_t vertex_colors = 0;         // color: `v x y z r g b [a]`, PLY/OFF vertex colours
  std::uint64_t face_colors = 0;           // color: OFF colour after a face's indices, PLY face colours
  std::uint64_t groups = 0;                // group: `g` and `o` lines
  std::uint64_t materials = 0;             // material: `usemtl` and `mtllib` lines
  std::uint64_t smoothing = 0;             // smoothing: `s` lines
  std::uint64_t tags = 0;                  // tag: OpenSubdiv `t` lines (creases, corners, ...) that parse
  std::uint64_t comments = 0;  // comment: lines of the leading comment block (PLY: header comments)
  std::vector<std::string> leading_comments;  // comment: their text (leading_comments())
  std::uint64_t vertex_weights = 0;           // extra: `v x y z w`
  // extra: OBJ lines that carry no geometry and that qsp does not understand (`vp`, `cstype` and the
  // other free-form attributes, `usemap`, a malformed tag, a stray line of prose), which the Mesh
  // readers keep as text; `first_kept` is the first one's line and what it is.
  std::uint64_t kept_lines = 0;
  ReadWarning first_kept;
  std::uint64_t other_properties = 0;    // extra: PLY properties qsp does not know (one per element)
  std::uint64_t obj_info = 0;            // extra: PLY `obj_info` header lines
  std::vector<std::uint32_t> face_line;  // per face: 1-based line it starts on (0 if not from text)
  // Coordinates whose value float32 does not hold (text with more digits than float32 keeps, a float64
  // or an integer beyond 2^24 in PLY): each is read as its nearest float32, so writing the mesh back
  // changes them. A caller that writes positions refuses or says so (the CLI: compress and reorder
  // refuse unless --float32, layout warns).
  std::uint64_t rounded_coordinates = 0;
  RoundedCoordinate first_rounded;  // the first such coordinate in the file

  // The categories of everything counted above; 0 for positions and quads only.
  unsigned categories() const;
  bool has_extra_data() const { return categories() != 0; }
  // What was seen in `categories`, each category's counts followed by its name: "8 texture coordinates,
  // 1 face with texture coordinate indices (uv), 1 line qsp keeps only as text, the first at
  // SOURCE:3: unknown statement 'This' (extra)"; empty if nothing.
  std::string describe_extra_data(std::string_view source, unsigned categories = kCategoryAll) const;
  // "SOURCE:12: vertex 3 has 0.1234567891234, which float32 holds only as 0.12345679 (and 5 more
  // coordinates)", empty if no coordinate was rounded.
  std::string describe_rounding(std::string_view source) const;
  // Counts a rounded coordinate, keeping the first one's place and value.
  void note_rounded(std::uint64_t line, std::uint64_t vertex, std::string_view value, float nearest);
  // Counts a kept line, keeping the first one's place and what it is.
  void note_kept(std::uint64_t line, std::string_view what);
};

// Parse OBJ text. `source` names the input in messages ("file.obj:12: ..."). Accepts v/vt/vn face
// syntax, negative (relative) indices, comments, o/g/s/usemtl/mtllib/t lines, CRLF, trailing
// whitespace; lines without geometry it does not understand (as read_obj_mesh keeps them) are counted
// in ReadReport::kept_lines. Refuses (Error with source:line): non-quad faces (count + first examples),
// vertex index 0 or out of range (texture coordinate and normal indices are checked for syntax only), a
// face repeating a vertex, malformed numbers and known statements, NaN/inf coordinates, `l`/`p`
// elements and free-form geometry (curv, curv2, surf).
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

// Write OBJ/OFF text, `comments` first (a '#' line each: the leading comment block, as
// leading_comments() reads it back). Floats use the shortest text that reads back to the same float
// (std::to_chars), so read(write(m)) == m bit for bit for a mesh the readers accept (a face that repeats
// a vertex is written as it is and refused on reading; a comment is not checked for line breaks). Throws
// Error: kBadIndex (a face names a vertex out of range), kBadNumber (a coordinate is not finite), kLimit
// (past kMaxVertices or kMaxFaces), kUsage (positions or quads end inside an entry, as the Mesh writers).
// Everything is checked before it is written, so safe on untrusted input. Never touches files.
std::string write_obj(const QuadMesh& mesh, const std::vector<std::string>& comments = {});
std::string write_off(const QuadMesh& mesh, const std::vector<std::string>& comments = {});

// ---------------------------------------------------------------------------------------------
// Exact reading into a Mesh

// What a reader saw besides the mesh.
struct ReadNotes {
  static constexpr std::size_t kMaxWarnings = 20;
  std::vector<std::uint32_t> face_line;  // per face: 1-based line it starts on (0 if not from text)
  // One per line kept as text (Mesh::verbatim, in file order: warnings[0] is the first kept line, the
  // one ReadReport::first_kept names), the first kMaxWarnings.
  std::vector<ReadWarning> warnings;
  std::uint64_t warning_count = 0;  // all of them (Mesh::verbatim.size())
  // The reader's counts of what it read, as read_obj and read_off report them (OBJ and OFF; empty for
  // PLY): no face lines (face_line above) and no rounded coordinates (this reader keeps them exactly).
  ReadReport counts;
  bool has_counts = false;
  // "file.obj:3: kept as text ...", one line each, and "(and N more)"; empty without warnings.
  std::string describe_warnings(std::string_view source) const;
};

// Parse OBJ text into a Mesh, keeping everything: faces of any degree >= 3 in the file's corner
// order; numbers exactly (qsp::Precision: float32 where its shortest text is the text's value, else
// float64 up to 17 significant digits, else the decimal digits); `v x y z [w | r g b [a]]`; `vt` (1 to 3
// components; a shorter one is padded with the OBJ default 0), `vn`, their per-corner indices (v/vt/vn,
// negative indices resolved); o, g, usemtl, s per face; mtllib; OpenSubdiv `t` tags; comment lines; and the
// order of all of them (Mesh::statements). Lines qsp does not understand but that carry no geometry (vp,
// cstype and other free-form attributes, usemap, malformed tags, a stray line of prose) are kept as
// text, in place, with a warning in `notes`. Refuses (Error with source:line): index 0 or out of
// range (vertices, texture coordinates, normals, tag indices), a face with fewer than 3 corners or
// repeating a vertex, malformed numbers and known statements, NaN/inf, numbers beyond float64's range,
// `l`/`p` elements and free-form geometry (curv, curv2, surf), vertices that disagree on having
// colours, and the limits. Safe on untrusted input.
Mesh read_obj_mesh(std::string_view text, std::string_view source, ReadNotes* notes = nullptr);

// Parse OFF text into a Mesh: [ST][C][N]OFF headers, per-vertex normals, colours (3 or 4, the same
// for every vertex) and texture coordinates (corner arrays then equal corner_vertices), faces of any
// degree with optional colours (1, 3 or 4 numbers, the same for every face), comment lines. Refuses
// as read_obj_mesh and read_off. Safe on untrusted input.
Mesh read_off_mesh(std::string_view text, std::string_view source, ReadNotes* notes = nullptr);

// Read PLY bytes into a Mesh: every vertex and face property with its name and type (binary values
// bit for bit, ASCII values exactly as text), x/y/z to positions, nx/ny/nz, u/v (s/t) and
// red/green/blue[/alpha] to per-vertex normals, texture coordinates and colours, face
// red/green/blue[/alpha] to face colours, the rest to Mesh::vertex_properties / face_properties;
// comments and obj_info lines; the header's layout (Mesh::ply). Refuses as read_ply, except that
// faces may have any degree >= 3. Safe on untrusted input.
Mesh read_ply_mesh(std::string_view bytes, const std::string& source, ReadNotes* notes = nullptr);

// Read a mesh file into a Mesh by extension (`-` = standard input, needs `format`). Errors as
// read_mesh_file.
Mesh read_mesh(const std::string& path, ReadNotes* notes = nullptr, MeshFormat format = MeshFormat::kUnknown);

// ---------------------------------------------------------------------------------------------
// Writing a Mesh

struct WriteOptions {
  bool keep_order = true;  // follow Mesh::statements / Mesh::ply when present (else canonical order)
  PlyFormat ply_format = PlyFormat::kAscii;  // when the mesh has no PLY layout
  bool ply_keep_format = true;               // the layout's own format when it has one
};

// Write a Mesh as OBJ text: the same statements in the same order when the mesh has its statement
// order (and keep_order), else comments, mtllib, kept lines, v, vt, vn, then faces with o, g, usemtl
// and s where they change, then tags (the faces in their order, but where a face without a label of a
// kind comes after faces with one, which OBJ cannot say, the faces with fewer labels first). Numbers as
// the shortest text denoting their exact value. Throws Error(kUnsupported) naming what OBJ cannot hold
// (face colours, PLY properties, faces whose missing labels no order can write) and the --drop
// category that removes it; kUsage when the
// mesh breaks an invariant of check_mesh (a face repeating a vertex is written as it is) or the
// statement order does not match the per-face labels. Safe on any mesh.
std::string write_obj_mesh(const Mesh& mesh, const WriteOptions& options = {});

// Write a Mesh as OFF text ([ST][C][N]OFF as the data needs). Throws Error(kUnsupported) naming what
// OFF cannot hold (texture coordinates or normals per corner, groups, materials, smoothing, tags,
// kept lines, PLY properties, vertex weights) and how to drop it; kUsage as write_obj_mesh.
std::string write_off_mesh(const Mesh& mesh);

// Write a Mesh as PLY (ASCII or binary): the file's own header layout when the mesh has one, with a
// property's type widened to double where its values need it. Throws Error(kUnsupported) naming what
// PLY cannot hold (per-corner texture coordinates or normals, groups, materials, smoothing, tags,
// kept lines, vertex weights; decimals beyond float64 in binary) and how to drop it; kUsage as
// write_obj_mesh.
std::string write_ply_mesh(const Mesh& mesh, const WriteOptions& options = {});

// The writer for `format` (kObj, kOff, kPly); kUsage for others.
std::string write_mesh(const Mesh& mesh, MeshFormat format, const WriteOptions& options = {});

// The leading comment block of OBJ or OFF text (licence and copyright lines, as MakeHuman and
// OpenSubdiv files carry them): the text after the '#' of each comment line from the start (after a
// UTF-8 byte order mark, and after an OFF keyword line, where OFF writers put it) up to the first line
// that is neither blank nor a comment, without its line
// end (LF, CRLF or a lone CR: so no text holds a CR or LF). Blank lines between them are not kept.
// Safe on untrusted input; reads only the block.
std::vector<std::string> leading_comments(std::string_view text);

// Read a whole file (or stdin for "-") into memory. Throws Error(kIo) with the path and reason.
std::string read_file_bytes(const std::string& path);

// Write bytes atomically: to an unnamed temporary file in the target's folder (O_TMPFILE; a named
// hidden one where unsupported), then link it into place, or in place of an existing file by
// exchanging their names and removing the old one, so a process killed at any moment leaves no
// partial output (at worst, killed between those two steps, the old file under a hidden name). With
// `sync` the file is flushed to disk (fsync) before it gets its name and the folder after, so a power
// cut cannot leave it short either (gzip's --synchronous); without, as gzip, zstd and Draco write by
// default, the system flushes it later (that wait was a tenth of decompressing a 19k-vertex mesh), and
// a power cut before then can leave the new file short, the old one gone (ext4 wrote out a file
// renamed over another at once, 0.2-3 ms a run; exchanging names does not ask that). Refuses (kIo) to
// replace an existing file unless `overwrite`; "-" writes stdout; an existing device or FIFO (e.g.
// /dev/full) is written in place, never replaced. On any failure the temporary file is removed and
// Error(kIo) says why (e.g. "No space left on device").
void write_file_atomic(const std::string& path, std::string_view bytes, bool overwrite, bool sync = false);

// Test seam: `hook` (nullptr, the default, for none) is called by write_file_atomic once the output is
// complete (and with `sync` flushed) in its temporary file, just before it gets its name. The CLI sets it
// only for tests (QSP_TEST_STOP_BEFORE_RENAME), which stop the process there to kill it inside that window.
// Not to be changed while another thread writes.
void set_before_rename_hook(void (*hook)());

}  // namespace qsp
