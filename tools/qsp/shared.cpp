#include "shared.h"

#include <sys/stat.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <system_error>

namespace qsp::cli {
namespace fs = std::filesystem;

namespace {

// `path` with every symbolic link on the way resolved, the last component too even when its target
// does not exist yet (a dangling link still names the file a write through it would create).
fs::path resolved(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::absolute(path, ec);
  if (ec) return fs::path(path);
  for (int hops = 0; hops < 40 && fs::is_symlink(p, ec); ++hops) {
    const fs::path target = fs::read_symlink(p, ec);
    if (ec) break;
    p = target.is_absolute() ? target : p.parent_path() / target;
  }
  const fs::path c = fs::weakly_canonical(p, ec);
  return ec ? p.lexically_normal() : c;
}

// What makes two names one file: the same device and inode if it exists (hard links), else the same
// resolved path.
struct FileId {
  bool exists = false;
  dev_t dev = 0;
  ino_t ino = 0;
  fs::path path;
};

FileId file_id(const std::string& name) {
  FileId id;
  struct stat st {};
  if (::stat(name.c_str(), &st) == 0) {
    id.exists = true;
    id.dev = st.st_dev;
    id.ino = st.st_ino;
  }
  id.path = resolved(name);
  return id;
}

bool same(const FileId& a, const FileId& b) {
  if (a.exists && b.exists) return a.dev == b.dev && a.ino == b.ino;
  return a.path == b.path;
}

}  // namespace

void check_outputs(const std::vector<std::string>& inputs, const std::vector<Output>& outputs) {
  std::vector<FileId> in_ids;
  for (const std::string& in : inputs) in_ids.push_back(in == "-" ? FileId{} : file_id(in));
  std::vector<FileId> out_ids;
  const Output* stdout_by = nullptr;
  for (const Output& out : outputs) {
    if (out.path == "-") {
      if (stdout_by)
        throw Error(ErrorCode::kIo, "standard output (-) is named twice, by " + stdout_by->named_by +
                                        " and by " + out.named_by + "; send one of them to a file");
      stdout_by = &out;
      out_ids.emplace_back();
      continue;
    }
    const FileId id = file_id(out.path);
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      if (inputs[i] == "-" || !same(id, in_ids[i])) continue;
      const std::string how = out.path == inputs[i] ? "" : " (" + inputs[i] + ", the same file)";
      throw Error(ErrorCode::kIo, out.path + ": is an input file" + how +
                                      "; refusing to write over it (name another output)");
    }
    for (std::size_t j = 0; j < out_ids.size(); ++j) {
      if (outputs[j].path == "-" || !same(id, out_ids[j])) continue;
      throw Error(ErrorCode::kIo, out.path + ": would be written twice, for " + outputs[j].named_by +
                                      " and for " + out.named_by + "; give each output its own name");
    }
    out_ids.push_back(id);
  }
}

namespace {

// What write_output refuses before writing: a folder, and an existing file without -f. Returns whether
// `path` exists (lstat: a link counts, dangling or not).
bool check_writable(const std::string& path, const WriteOptions& o, struct stat& st) {
  const bool exists = ::lstat(path.c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode))
    throw Error(ErrorCode::kIo, path + ": is a folder; name a file to write (" + o.other_ways + ")");
  if (exists && !o.force)
    throw Error(ErrorCode::kIo, path + ": already exists; pass -f to replace it, or " + o.other_ways);
  return exists;
}

}  // namespace

void refuse_existing(const std::vector<Output>& outputs, const WriteOptions& o) {
  struct stat st {};
  for (const Output& out : outputs)
    if (out.path != "-") check_writable(out.path, o, st);
}

void write_output(const std::string& path, std::string_view bytes, const WriteOptions& o) {
  if (path == "-") return write_file_atomic(path, bytes, true);  // nothing to flush
  struct stat st {};
  const bool exists = check_writable(path, o, st);
  if (exists && S_ISLNK(st.st_mode)) {
    // Replacing the link by a regular file would cut whatever it points to out of the user's setup.
    const std::string target = resolved(path).string();
    if (!o.quiet)
      std::fprintf(stderr, "qsp: %s is a symbolic link: writing through it to %s (the link stays)\n",
                   path.c_str(), target.c_str());
    return write_file_atomic(target, bytes, true, o.sync);
  }
  write_file_atomic(path, bytes, o.force, o.sync);
}

void add_sync_flag(CLI::App* command, bool& sync) {
  command->add_flag("--sync", sync,
                    "Flush each output to disk before giving it its name, so a power cut cannot leave it "
                    "short (slower; as gzip --synchronous). Without it an interrupted run still leaves "
                    "no partial file");
}

MeshFormat parse_format_option(const std::string& value) {
  if (value.empty()) return MeshFormat::kUnknown;
  const MeshFormat f = format_from_path("x." + value);
  if (f == MeshFormat::kUnknown || f == MeshFormat::kQsp)
    throw CLI::ValidationError("--format " + value + ": must be obj, off or ply");
  return f;
}

void add_format_option(CLI::App* cmd, std::string& value) {
  cmd->add_option("--format", value,
                  "Mesh format of standard input or of files whose name does not say: obj, off or ply "
                  "(default: detected, OFF and ply by their first line, else OBJ)")
      ->check(CLI::IsMember({"obj", "off", "ply"}));
}

namespace {

// Refuses (kIo) a path that is a folder, saying so and how to name the files in it.
void refuse_folder(const std::string& path) {
  std::error_code ec;
  if (path != "-" && fs::is_directory(path, ec)) {
    std::string dir = path;
    while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
    throw Error(ErrorCode::kIo,
                path + ": is a folder, not a mesh file (give the files in it, e.g. " + dir + "/*.obj)");
  }
}

// `format` where it applies: to standard input and to a name whose extension says no format.
MeshFormat format_for(const std::string& path, MeshFormat format) {
  return path == "-" || format_from_path(path) == MeshFormat::kUnknown ? format : MeshFormat::kUnknown;
}

// The format of mesh bytes from their first line: "OFF" (also COFF, NOFF, ...) or "ply" magic, else
// OBJ; kQsp for the .qsp magic.
MeshFormat detect_format(std::string_view bytes) {
  if (bytes.substr(0, 4) == "\x89QSP") return MeshFormat::kQsp;
  if (bytes.substr(0, 4) == "ply\n" || bytes.substr(0, 5) == "ply\r\n") return MeshFormat::kPly;
  // OFF's header keyword: OFF with optional ST, C, N, 4 and n prefixes (COFF, NOFF, STOFF, ...).
  std::size_t n = 0;
  while (n < bytes.size() && n < 16 && std::string_view("STCN4n").find(bytes[n]) != std::string_view::npos)
    ++n;
  if (bytes.substr(n, 3) == "OFF" &&
      (bytes.size() == n + 3 || std::string_view(" \t\r\n").find(bytes[n + 3]) != std::string_view::npos))
    return MeshFormat::kOff;
  return MeshFormat::kObj;
}

[[noreturn]] void refuse_qsp(const std::string& path) {
  throw Error(ErrorCode::kUnsupported,
              path + ": is .qsp compressed data, not a mesh (qsp decompress reads it)");
}

// The format of bytes read from `path` whose name says none: by detect_format, OBJ (no magic) on
// standard input only; kQsp for .qsp bytes.
MeshFormat format_of_bytes(std::string_view bytes, const std::string& path) {
  const MeshFormat detected = detect_format(bytes);
  if (detected == MeshFormat::kObj && path != "-")
    throw Error(ErrorCode::kUnsupported,
                path + ": unknown mesh format (expected .obj, .off or .ply; give --format obj if it is OBJ)");
  return detected;
}

QuadMesh parse_quads(std::string_view bytes, const std::string& path, MeshFormat format, ReadReport* report) {
  if (format == MeshFormat::kOff) return read_off(bytes, path, report);
  if (format == MeshFormat::kPly) return read_ply(bytes, path, report);
  return read_obj(bytes, path, report);
}

// The detecting half of read_input_mesh, on bytes already read from `path`.
QuadMesh read_mesh_bytes(std::string_view bytes, const std::string& path, ReadReport* report) {
  const MeshFormat detected = format_of_bytes(bytes, path);
  if (detected == MeshFormat::kQsp) refuse_qsp(path);
  return parse_quads(bytes, path, detected, report);
}

}  // namespace

QuadMesh read_input_mesh(const std::string& path, MeshFormat format, ReadReport* report) {
  refuse_folder(path);
  format = format_for(path, format);
  if (format == MeshFormat::kUnknown && path != "-") format = format_from_path(path);
  if (format != MeshFormat::kUnknown) return read_mesh_file(path, report, format);
  // Standard input, or a name that says nothing: the bytes say it (OBJ has no magic: the default on
  // standard input; a file of unknown name must be OFF or PLY by its magic, or be named).
  return read_mesh_bytes(read_file_bytes(path), path, report);
}

void rethrow_located(const Error& e, const std::string& path, const ReadReport& report) {
  const std::int64_t f = e.face();
  if (f >= 0 && static_cast<std::size_t>(f) < report.face_line.size() && report.face_line[f] != 0)
    throw Error(e.code(), path + ":" + std::to_string(report.face_line[f]) + ": " + e.what(), f);
  if (f >= 0) throw Error(e.code(), path + ": " + e.what(), f);
  throw e;
}

Input read_input(const std::string& path, MeshFormat format) {
  refuse_folder(path);
  format = format_for(path, format);
  Input in;
  if (format == MeshFormat::kUnknown && format_from_path(path) == MeshFormat::kQsp) {
    in.qsp = true;
    in.bytes = read_file_bytes(path);
  } else if (format == MeshFormat::kUnknown && format_from_path(path) == MeshFormat::kUnknown) {
    // Standard input or a name that says nothing: read once, then look at the magic.
    std::string bytes = read_file_bytes(path);
    if (detect_format(bytes) == MeshFormat::kQsp) {
      in.qsp = true;
      in.bytes = std::move(bytes);
    } else {
      in.mesh = read_mesh_bytes(bytes, path, &in.report);
    }
  } else {
    in.mesh = read_input_mesh(path, format, &in.report);
  }
  return in;
}

QuadMesh read_mesh_or_qsp(const std::string& path, ReadReport& report, MeshFormat format) {
  Input in = read_input(path, format);
  report = std::move(in.report);
  if (!in.qsp) return std::move(in.mesh);
  QuadMesh mesh = decode_named(in.bytes, path);
  report.leading_comments = comments_named(in.bytes, path);
  report.comments = report.leading_comments.size();
  return mesh;
}

std::vector<std::string> comments_named(std::string_view bytes, const std::string& path) {
  try {
    return file_comments(bytes);
  } catch (const Error& e) {
    throw Error(e.code(), path + ": " + e.what());
  }
}

QuadMesh decode_named(std::string_view bytes, const std::string& path, const DecodeLimits& limits) {
  try {
    return decode(bytes, limits);
  } catch (const Error& e) {
    throw Error(e.code(), path + ": " + e.what());
  }
}

LoadedMesh with_adjacency(QuadMesh mesh, ReadReport report, const std::string& path) {
  LoadedMesh out{std::move(mesh), {}, std::move(report)};
  try {
    out.adjacency = build_adjacency(out.mesh);
  } catch (const Error& e) {
    rethrow_located(e, path, out.report);
  }
  return out;
}

MatchInput prepare_located(QuadMesh mesh, const std::string& path, const ReadReport& report) {
  try {
    return prepare_match(std::move(mesh));
  } catch (const Error& e) {
    rethrow_located(e, path, report);
  }
}

namespace {

// The coordinates float32 does not hold, counted into `r` (refused where they do not round to a finite
// nonzero float, as the quad reader refuses them).
void count_rounded(const Mesh& m, ReadReport& r, const std::string& path) {
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const float f = m.positions.f32[i];
    const double exact = m.positions.approx(i);
    if (!std::isfinite(f) || (f == 0.0f && exact != 0.0))
      throw Error(ErrorCode::kBadNumber, path + ": vertex " + std::to_string(i / 3) +
                                             " has a coordinate outside the float32 range (it does not round "
                                             "to a finite nonzero float)");
    if (static_cast<double>(f) == exact) continue;
    if (r.rounded_coordinates++ == 0) {
      char text[32];
      const auto end = std::to_chars(text, text + sizeof text, exact).ptr;
      r.first_rounded = {0, i / 3, std::string(text, end), f};  // line: the exact reader does not say
    }
  }
}

// What the quad reader's report would say of a mesh the exact reader read: its extra data by category
// (the reader's own counts for OBJ and OFF), its face lines, and the coordinates float32 does not hold.
ReadReport report_of(const Mesh& m, ReadNotes&& notes, const std::string& path) {
  ReadReport r;
  if (notes.has_counts) {  // OBJ and OFF: the reader's own counts, the quad reader's words
    r = std::move(notes.counts);
    r.face_line = std::move(notes.face_line);
    r.rounded_coordinates = 0, r.first_rounded = {};  // counted here, for every format alike
    count_rounded(m, r, path);
    return r;
  }
  const Extras x = extras(m);
  r.texcoords = x.texcoords;
  r.normals = x.normals;
  r.vertex_colors = x.vertex_colors;
  r.face_colors = x.face_colors;
  r.groups = x.objects + x.groups;
  r.materials = x.materials + x.material_libraries;
  r.smoothing = x.smoothing;
  r.tags = x.tags;
  r.vertex_weights = x.vertex_weights;
  r.kept_lines = x.verbatim;
  if (!notes.warnings.empty()) r.first_kept = notes.warnings.front();
  r.other_properties = m.vertex_properties.size() + m.face_properties.size();
  r.obj_info = m.ply.obj_info.size();
  r.face_line = std::move(notes.face_line);
  count_rounded(m, r, path);
  return r;
}

// A mesh file the quad reader refused for a face that is not a quad, parsed again by the exact reader.
void read_polygons(PolygonInput& in, std::string_view bytes, const std::string& path, MeshFormat format,
                   unsigned keep) {
  ReadNotes notes;
  Mesh m = format == MeshFormat::kOff   ? read_off_mesh(bytes, path, &notes)
           : format == MeshFormat::kPly ? read_ply_mesh(bytes, path, &notes)
                                        : read_obj_mesh(bytes, path, &notes);
  in.report = report_of(m, std::move(notes), path);
  // The leading comment block, as the quad readers report it (PLY: the header's comments).
  in.report.leading_comments = format == MeshFormat::kPly ? m.comments : leading_comments(bytes);
  in.report.comments = in.report.leading_comments.size();
  // Kept texture coordinates, normals and colours are float32: count those the text says more precisely.
  // A value float32 holds: a float32 itself (binary PLY doubles that are float32 values), or the value its
  // float32's shortest text denotes (2.7 in a list that also has 1.4e-45, whose float32 prints as 1e-45:
  // 2.7's float64 is not its float32's value, but "2.7" is its float32's text).
  const auto held = [](const Numbers& n, std::size_t i, std::size_t& next_decimal) {
    if (next_decimal < n.decimals.size() && n.decimals[next_decimal].index == i) return ++next_decimal, false;
    if (static_cast<double>(n.f32[i]) == n.f64[i]) return true;
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, n.f32[i]).ptr;
    double value = 0;
    std::from_chars(text, end, value);
    return value == n.f64[i];
  };
  const auto rounded = [&in, &held](const Numbers& n, std::size_t per, const char* what, const char* keyword,
                                    unsigned category) {
    if (n.precision == Precision::kFloat32) return;
    std::size_t next_decimal = 0;
    if (!n.decimals.empty() && in.values_beyond_float64 == 0) {
      const DecimalNumber& d = n.decimals.front();
      const std::size_t t = d.index / per;
      in.first_value_beyond_float64 =
          std::string(what) + " " + std::to_string(t) +
          (keyword ? " (OBJ `" + std::string(keyword) + "` " + std::to_string(t + 1) + ")" : std::string()) +
          " has " + (d.negative ? "-" : "") + d.digits.substr(0, 1) + "." + d.digits.substr(1) + "e" +
          std::to_string(d.exponent + static_cast<std::int32_t>(d.digits.size()) - 1);
    }
    in.values_beyond_float64 += n.decimals.size();
    for (std::size_t i = 0; i < n.size(); ++i) {
      if (held(n, i, next_decimal)) continue;
      in.rounded_categories |= category;
      if (in.rounded_texcoords++ == 0) {
        char value[32];
        const auto end = std::to_chars(value, value + sizeof value, n.approx(i)).ptr;  // shortest
        const std::size_t t = i / per;
        in.first_rounded_texcoord =
            std::string(what) + " " + std::to_string(t) +
            (keyword ? " (OBJ `" + std::string(keyword) + "` " + std::to_string(t + 1) + ")"
                     : std::string()) +
            " has " + std::string(value, end);
      }
    }
  };
  const bool obj = format == MeshFormat::kObj;
  if (keep & kCategoryUv)
    rounded(m.texcoords, std::max<std::size_t>(m.texcoord_components, 1), "texture coordinate",
            obj ? "vt" : nullptr, kCategoryUv);
  if (keep & kCategoryNormal) rounded(m.normals, 3, "normal", obj ? "vn" : nullptr, kCategoryNormal);
  if (keep & kCategoryColor) {
    rounded(m.vertex_colors, std::max<std::size_t>(m.vertex_color_components, 1), "vertex colour",
            obj ? "v" : nullptr, kCategoryColor);
    rounded(m.face_colors, std::max<std::size_t>(m.face_color_components, 1), "face colour", nullptr,
            kCategoryColor);
  }
  // Properties are kept as binary64: refuse what it does not hold rather than round it.
  if (keep & kCategoryExtra) {
    const auto beyond = [&](const Numbers& n, const std::string& what) {
      if (n.precision == Precision::kDecimal && !n.decimals.empty())
        throw Error(ErrorCode::kUnsupported,
                    path + ": " + what + " value " + std::to_string(n.decimals.front().index) +
                        " has more digits than float64 holds; a .qsp keeps binary64 property values: pass "
                        "--drop extra");
    };
    beyond(m.vertex_weights, "the vertex weights (v x y z w), one per vertex:");
    for (const Property& q : m.vertex_properties) beyond(q.values, "PLY vertex property '" + q.name + "'");
    for (const Property& q : m.face_properties) beyond(q.values, "PLY face property '" + q.name + "'");
  }
  if (keep & kCategoryTag)
    for (std::size_t t = 0; t < m.tags.size(); ++t)
      if (m.tags[t].floats.precision == Precision::kDecimal)
        throw Error(ErrorCode::kUnsupported,
                    path + ": tag " + std::to_string(t) + " ('" + m.tags[t].name +
                        "') has a value of more digits than float64 holds; a .qsp keeps binary64 tag values: "
                        "pass --drop tag");
  // Positions are kept as float64 where float32 does not hold them: count those float64 does not hold.
  for (const DecimalNumber& d : m.positions.decimals) {
    if (in.beyond_float64++) continue;
    in.first_beyond_float64 = "vertex " + std::to_string(d.index / 3) + " has " + (d.negative ? "-" : "") +
                              d.digits.substr(0, 1) + "." + d.digits.substr(1) + "e" +
                              std::to_string(d.exponent + static_cast<std::int32_t>(d.digits.size()) - 1);
  }
  in.polygons = to_polygon_mesh(std::move(m), keep);
}

// A .qsp: a polygon mesh (its polygons section, 3.1) is decoded, so that every subcommand taking polygon
// meshes treats it as the mesh it was compressed from; a quad .qsp as `qsp` says. The container is
// looked at first, so that the file is decoded once, by the reader it needs.
void read_qsp(PolygonInput& in, std::string&& bytes, const std::string& path, QspInput qsp) {
  if (qsp == QspInput::kRefused) refuse_qsp(path);
  in.from_qsp = true;
  try {
    if (holds_polygons(bytes)) {
      in.polygons = decode_polygons(bytes);
      if (in.polygons.texcoord_components)
        in.report.texcoords = in.polygons.texcoords.size() / in.polygons.texcoord_components;
    } else if (qsp == QspInput::kDecoded) {
      in.mesh = decode(bytes);
      in.quads = true;
    } else {
      in.qsp = true;
      in.bytes = std::move(bytes);
      return;
    }
    in.report.leading_comments = file_comments(bytes);
  } catch (const Error& e) {
    throw Error(e.code(), path + ": " + e.what());
  }
  in.report.comments = in.report.leading_comments.size();
  if (qsp == QspInput::kBytes && !in.quads) in.bytes = std::move(bytes);  // a polygon file's sections
}

// Whether a file the quad reader read needs the exact reader too: for what it keeps of texture
// coordinates, normals, labels, extra data, or coordinates float32 does not hold (unless rounded).
bool needs_exact(const ReadReport& r, unsigned keep, Coordinates coordinates) {
  return (r.categories() & keep & kPolygonMeshCategories) ||
         (r.rounded_coordinates && coordinates == Coordinates::kExact) ||
         ((r.kept_lines || r.vertex_weights || r.other_properties || r.obj_info) && (keep & kCategoryExtra));
}

// Whether the last face statement of OBJ text has a slash: corners naming texture coordinates or
// normals. One line from the end, not a scan of the file.
bool last_face_has_corner_refs(std::string_view text) {
  std::size_t end = text.size();
  for (int lines = 0; end > 0 && lines < 64; ++lines) {  // past trailing blank lines, comments, groups
    const std::size_t start = text.rfind('\n', end - 1);
    const std::size_t from = start == std::string_view::npos ? 0 : start + 1;
    std::string_view line = text.substr(from, end - from);
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first != std::string_view::npos && line.size() > first + 1 && line[first] == 'f' &&
        (line[first + 1] == ' ' || line[first + 1] == '\t'))
      return line.find('/') != std::string_view::npos;
    if (start == std::string_view::npos) break;
    end = start;
  }
  return false;
}

}  // namespace

PolygonInput read_polygon_input(const std::string& path, MeshFormat format, QspInput qsp, unsigned keep,
                                Coordinates coordinates) {
  refuse_folder(path);
  format = format_for(path, format);
  if (format == MeshFormat::kUnknown && path != "-") format = format_from_path(path);
  if (format == MeshFormat::kQsp && qsp == QspInput::kRefused) refuse_qsp(path);  // before reading it
  // Read once: the exact reader and the leading comments read the same bytes again where the quad
  // reader refuses a face.
  std::string bytes = read_file_bytes(path);
  if (format == MeshFormat::kUnknown) format = format_of_bytes(bytes, path);
  PolygonInput in;
  if (format == MeshFormat::kQsp) {
    read_qsp(in, std::move(bytes), path, qsp);
    return in;
  }
  if (format == MeshFormat::kObj && (keep & (kCategoryUv | kCategoryNormal)) &&
      last_face_has_corner_refs(bytes)) {
    // Faces naming texture coordinates or normals: the exact reader alone (reading the text twice, quad
    // reader first, was an eighth of compressing mh_female_generic with its UVs). Where the quad reader
    // says more (the line of a coordinate float32 does not hold), or the exact reader refuses the file, or
    // the quad mesh would do, the two readers as below: their words and their mesh, as always.
    try {
      read_polygons(in, bytes, path, format, keep);
      if (in.report.rounded_coordinates == 0 && in.beyond_float64 == 0 &&
          needs_exact(in.report, keep, coordinates))
        return in;
    } catch (const Error&) {
    }
    in = PolygonInput{};
  }
  try {
    in.mesh = parse_quads(bytes, path, format, &in.report);
    in.quads = true;
  } catch (const Error& e) {
    if (e.code() != ErrorCode::kNotQuad) throw;
    read_polygons(in, bytes, path, format, keep);
    return in;
  }
  // Texture coordinates, labels and coordinates float32 does not hold come from the exact reader, which
  // the quad reader's report says it needs.
  if (needs_exact(in.report, keep, coordinates)) {
    ReadReport report = std::move(in.report);  // the same kinds; its words for the quad path's messages
    in.mesh = {};
    in.quads = false;
    read_polygons(in, bytes, path, format, keep);
    in.report = std::move(report);
  }
  return in;
}

PolygonMesh polygons_of(PolygonInput&& in) {
  return in.quads ? polygon_mesh(std::move(in.mesh)) : std::move(in.polygons);
}
PolygonMesh polygons_of(const PolygonInput& in) { return in.quads ? polygon_mesh(in.mesh) : in.polygons; }

bool polygon_path_takes(const Error& e) {
  return e.code() == ErrorCode::kNonManifold || e.code() == ErrorCode::kOrientation;
}

std::optional<MatchResult> match_as_quads(const PolygonMesh& a, const PolygonMesh& b,
                                          const MatchOptions& options) {
  const auto quads = [](const PolygonMesh& m) {
    for (std::size_t f = 0; f + 1 < m.face_offsets.size(); ++f)
      if (m.face_offsets[f + 1] - m.face_offsets[f] != 4) return false;
    return true;
  };
  if (!quads(a) || !quads(b)) return std::nullopt;
  try {
    return match(prepare_match(QuadMesh{a.positions, a.corners}),
                 prepare_match(QuadMesh{b.positions, b.corners}), options);
  } catch (const Error&) {
    return std::nullopt;
  }
}

PolygonMatchInput prepare_polygon_located(PolygonMesh mesh, const std::string& path,
                                          const ReadReport& report) {
  try {
    return prepare_polygon_match(std::move(mesh));
  } catch (const Error& e) {
    rethrow_located(e, path, report);
  }
}

unsigned DropOptions::categories() const {
  return (positions_only ? unsigned{kCategoryAll} : 0u) | (list.empty() ? 0u : parse_categories(list));
}

void add_drop_options(CLI::App* cmd, DropOptions& drop, const std::string& whose, unsigned kept,
                      const std::string& refused) {
  // What the subcommand keeps unless dropped is said first: it refuses only the rest.
  const std::string keeps = kept ? category_list(kept, ", ") + " and comment are kept unless dropped; " : "";
  cmd->add_option("--drop", drop.list,
                  "Drop " + whose + "data of these kinds (comma-separated: " +
                      category_list(kCategoryAll, ", ") + "); " + keeps +
                      (!refused.empty() ? refused
                       : kept           ? "a file with any of the others is refused unless they are dropped"
                                        : "a file with any of them is refused unless they are dropped") +
                      ". extra: lines qsp keeps only as text (vp, cstype, "
                      "a stray line of prose), vertex weights (v x y z w), other PLY properties, PLY "
                      "obj_info lines" +
                      (kept ? std::string(" (kept unless dropped)") : std::string()) +
                      ". comment: the leading comment block (licence lines), "
                      "which is kept unless dropped; later comments are never kept")
      ->type_name("LIST")
      ->check(CLI::Validator(
          [](std::string& value) {
            try {
              parse_categories(value);
            } catch (const Error& e) {
              return std::string(e.what());
            }
            return std::string();
          },
          ""));
  cmd->add_flag(
      "--positions-only", drop.positions_only,
      "Drop all of them (--drop " + category_list(kCategoryAll) + "): keep positions and faces only");
}

ReadReport refusable_extra(const ReadReport& report, unsigned keep) {
  ReadReport r = report;
  if (keep & kCategoryExtra) r.kept_lines = r.vertex_weights = r.other_properties = r.obj_info = 0;
  return r;
}

std::string refuse_extra_data(const std::string& path, const ReadReport& report, const std::string& what,
                              const DropOptions& drop, bool quiet, unsigned kept) {
  const unsigned has = report.categories() & ~(kept & ~drop.categories()), dropped = drop.categories() & has;
  if ((dropped | kKeptCategories) != (has | kKeptCategories))
    throw Error(ErrorCode::kUnsupported,
                path + ": has " + report.describe_extra_data(path, has & ~dropped & ~kKeptCategories) +
                    ", which " + what + " does not keep; pass --drop " +
                    category_list(report.categories() & ~kKeptCategories & ~kept) +
                    " (or --positions-only) to drop them");
  if (quiet || !dropped) return {};
  return "qsp: " + path + ": dropped " + report.describe_extra_data(path, dropped) + " (" +
         (drop.positions_only ? "--positions-only" : "--drop " + drop.list) + ")\n";
}

std::vector<std::string> kept_comments(const ReadReport& report, const DropOptions& drop) {
  return drop.categories() & kCategoryComment ? std::vector<std::string>{} : report.leading_comments;
}

void refuse_rounding(const std::string& path, const ReadReport& report, const std::string& what, bool float32,
                     bool quiet, const std::string& other_way) {
  if (report.rounded_coordinates == 0) return;
  if (!float32)
    throw Error(ErrorCode::kUnsupported, report.describe_rounding(path) + "; " + what +
                                             " keeps float32 coordinates: pass --float32 to round them" +
                                             (other_way.empty() ? "" : ", or " + other_way));
  if (!quiet)
    std::fprintf(stderr, "qsp: %s: rounded %llu %s to float32 (--float32)\n", path.c_str(),
                 static_cast<unsigned long long>(report.rounded_coordinates),
                 report.rounded_coordinates == 1 ? "coordinate" : "coordinates");
}

std::string drop_polygon_data(PolygonMesh& m, const std::string& path, const DropOptions& drop,
                              std::vector<std::string>* comments) {
  const unsigned d = drop.categories();
  unsigned had = qsp::drop(m, d);
  if (comments && (d & kCategoryComment) && !comments->empty()) had |= kCategoryComment, comments->clear();
  if (!had) return {};
  return "qsp: " + path + ": dropped its " + category_list(had, ", ") + " (" +
         (drop.positions_only ? "--positions-only" : "--drop " + drop.list) + ")\n";
}

void check_kept_values(const std::string& path, const PolygonInput& input, PolygonMesh& mesh,
                       const KeptRules& rules) {
  const ReadReport& report = input.report;
  const std::string& in = path;
  if (mesh.vertex_count() == 0 && !mesh.kept_lines.empty())
    throw Error(ErrorCode::kParse,
                in + ": not a mesh: no vertex, only " + report.describe_extra_data(in, kCategoryExtra));
  for (const std::string& line : mesh.kept_lines)
    if (const std::string why = kept_line_problem(line); !why.empty())
      throw Error(ErrorCode::kUnsupported, in + ": a line kept as text, '" + line + "', " + why + ", which " +
                                               rules.what +
                                               " cannot keep as text; pass --drop extra to drop the lines "
                                               "kept as text");
  if (!mesh.kept_lines.empty() && !rules.quiet && !rules.lines_note.empty())
    std::fprintf(stderr, "qsp: warning: %s: keeping %s; %s\n", in.c_str(),
                 report.describe_extra_data(in, kCategoryExtra).c_str(), rules.lines_note.c_str());
  // Coordinates float32 does not hold are kept as float64 unless rounded; float64 holds every text of
  // up to 17 significant digits.
  const bool lossless = !rules.quantized;
  if (rules.quantized || rules.float32) mesh.positions64.clear();
  if (lossless && !rules.float32 && input.beyond_float64)
    throw Error(ErrorCode::kUnsupported,
                in + ": " + input.first_beyond_float64 +
                    (input.beyond_float64 > 1
                         ? " (and " + std::to_string(input.beyond_float64 - 1) + " more coordinates like it)"
                         : std::string()) +
                    ", more digits than float64 holds; " +
                    (rules.what == ".qsp" ? "a lossless .qsp" : rules.what) +
                    " keeps float64 coordinates: pass --float32 to round them to float32" +
                    (rules.what == ".qsp" ? ", or --quantize BITS" : ""));
  if (lossless && rules.float32)
    refuse_rounding(in, report, rules.what == ".qsp" ? "a lossless .qsp" : rules.what, true, rules.quiet, "");
  // Texture coordinates, normals and colours float32 does not hold (the first named) are kept as
  // float64, as positions are, unless rounded: --float32, or their own --quantize-* (which rounds them
  // anyway); of more digits than float64 holds they are refused unless rounded.
  const unsigned kinds = input.rounded_categories;
  const std::string what = kinds == kCategoryNormal  ? "normal"
                           : kinds == kCategoryColor ? "colour"
                           : kinds == kCategoryUv    ? "texture coordinate"
                                                     : "texture coordinate, normal and colour";
  const unsigned rounded = rules.float32 ? kinds : kinds & rules.quantized_values;
  if (rounded & kCategoryUv) mesh.texcoords64.clear();
  if (rounded & kCategoryNormal) mesh.normals64.clear();
  if (rounded & kCategoryColor) mesh.vertex_colors64.clear(), mesh.face_colors64.clear();
  if (input.values_beyond_float64 && (kinds & ~rounded))
    throw Error(
        ErrorCode::kUnsupported,
        in + ": " + std::to_string(input.values_beyond_float64) + " " + what +
            " values have more digits than float64 holds (the first: " + input.first_value_beyond_float64 +
            "); " + (rules.what == ".qsp" ? "a lossless .qsp" : rules.what) + " keeps float64 " + what +
            "s: pass --float32 to round them, or --drop " + category_list(kinds));
  if (input.rounded_texcoords && rules.float32 && !rules.quiet)
    std::fprintf(stderr, "qsp: %s: rounded %llu %s values to float32 (--float32)\n", in.c_str(),
                 static_cast<unsigned long long>(input.rounded_texcoords), what.c_str());
}

void add_centering_option(CLI::App* cmd, Centering& value) {
  const std::map<std::string, Centering> names{
      {"component", Centering::kComponent}, {"mesh", Centering::kMesh}, {"none", Centering::kNone}};
  cmd->add_option(
         "--centering", value,
         "Positions compared to choose among symmetric isomorphisms: component (default), mesh, none")
      ->transform(CLI::CheckedTransformer(names));
}

int for_each_file(const std::vector<std::string>& files, const std::function<void(std::size_t)>& one,
                  const std::function<void(std::size_t, const std::string&)>& on_error) {
  int rc = 0;
  for (std::size_t i = 0; i < files.size(); ++i) {
    int code = 0;
    std::string message;
    try {
      one(i);
      continue;
    } catch (const Error& e) {
      code = exit_code_for(e.code());
      message = e.what();
    } catch (const CLI::ParseError& e) {
      code = exit_code(Outcome::kUsage);
      message = e.what();
    } catch (const std::bad_alloc&) {
      code = exit_code(Outcome::kInternal);
      message = files[i] + ": out of memory";
    }
    std::fflush(stdout);  // the error after the rows before it
    std::fprintf(stderr, "qsp: error: %s\n", message.c_str());
    if (on_error) on_error(i, message);
    if (rc == 0) rc = code;
  }
  return rc;
}

std::string name_meshes(std::string reason, const std::string& a, const std::string& b) {
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"A has ", a + " has "},
                                 {", B has ", ", " + b + " has "},
                                 {" of A:", " of " + a + ":"}}) {
    for (std::size_t at = reason.find(from); at != std::string::npos; at = reason.find(from, at + to.size()))
      reason.replace(at, from.size(), to);
  }
  return reason;
}

std::string mirror_hint(const std::string& a, const std::string& b) {
  return "; but " + b + " is " + a +
         " with every face reversed (mirrored, or turned inside out): pass --allow-mirror to accept "
         "orientation-reversing matches";
}

std::string nearest(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = word.size() / 4 + 2;  // more than this many edits is no longer a typo
  for (const std::string& c : candidates) {
    // Levenshtein distance, one row.
    std::vector<std::size_t> row(c.size() + 1);
    for (std::size_t j = 0; j <= c.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= word.size(); ++i) {
      std::size_t diag = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= c.size(); ++j) {
        const std::size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (word[i - 1] == c[j - 1] ? 0 : 1)});
        diag = up;
      }
    }
    if (row[c.size()] < best_d) {
      best_d = row[c.size()];
      best = c;
    }
  }
  return best;
}

void add_file_args(CLI::App* cmd, FileArgs& args, const std::string& what_in, const std::string& what_out) {
  cmd->add_option("FILES", args.positional,
                  what_in + "; - for standard input. A last name " + what_out +
                      " is the output of a single input (else each input is written beside itself)")
      ->required();
  cmd->add_option("-o,--output", args.output, "Output file for a single input (- for standard output)");
  cmd->add_option("--output-dir", args.output_dir, "Write each output into this folder (made if missing)");
  cmd->add_flag("-c,--stdout", args.to_stdout, "Write to standard output (a single input)");
}

std::vector<Job> plan_jobs(const FileArgs& a, const OutputNaming& naming) {
  std::vector<std::string> inputs = a.positional;
  Output given;
  if (!a.output.empty()) {
    given = {a.output, "-o"};
  } else if (inputs.size() >= 2 && (naming.is_output_name(inputs.back()) || inputs.back() == "-")) {
    // A last "-" is standard output, as it always was (`compress - -`: a filter).
    given = {inputs.back(), "OUT"};
    inputs.pop_back();
    if (inputs.size() > 1)
      throw CLI::ValidationError(given.path + ": an output name may follow a single input only; to " +
                                 naming.verb +
                                 " several files leave it out (each is written beside its input) or use "
                                 "--output-dir DIR");
  } else if (inputs.size() == 2 && !fs::exists(inputs[1]) && !fs::is_symlink(inputs[1]) &&
             fs::exists(inputs[0])) {
    // `compress in.obj out.obj`: surely meant as IN OUT, but an output name must say what it holds.
    throw CLI::ValidationError(inputs[1] + ": no such file to " + naming.verb +
                               "; if it is meant as the output, its name " + naming.rule);
  }
  const int ways = !given.path.empty() + !a.output_dir.empty() + a.to_stdout;
  if (ways > 1) throw CLI::ValidationError("give one of OUT, -o, --output-dir and -c");
  if (inputs.size() > 1 && (!given.path.empty() || a.to_stdout))
    throw CLI::ValidationError(
        std::string(a.to_stdout ? "-c" : "-o") + " names one output, but there are " +
        std::to_string(inputs.size()) +
        " inputs: use --output-dir DIR, or neither (each is written beside its input)");
  if (!a.output_dir.empty()) {
    std::error_code ec;
    fs::create_directories(a.output_dir, ec);
    if (!fs::is_directory(a.output_dir))
      throw Error(ErrorCode::kIo, a.output_dir + ": cannot use as --output-dir: " +
                                      (ec ? ec.message() : std::string("not a folder")));
  }
  std::vector<Job> jobs;
  std::vector<Output> outputs;
  for (const std::string& in : inputs) {
    Job job{in, "", false};
    if (a.to_stdout || (in == "-" && given.path.empty() && a.output_dir.empty())) {
      job.output = "-";
    } else if (!given.path.empty()) {
      job.output = given.path;
    } else if (in != "-") {
      job.output = naming.beside(in);
      job.derived = true;
      if (!job.output.empty() && !a.output_dir.empty())
        job.output = (fs::path(a.output_dir) / fs::path(job.output).filename()).string();
    } else {
      job.output = (fs::path(a.output_dir) / naming.stdin_name).string();
      job.derived = true;
    }
    if (!job.output.empty()) outputs.push_back({job.output, job.derived ? "input " + in : given.named_by});
    jobs.push_back(job);
  }
  check_outputs(inputs, outputs);
  return jobs;
}

int run_jobs(const FileArgs& args, const OutputNaming& naming, const std::function<void(const Job&)>& one) {
  const std::vector<Job> jobs = plan_jobs(args, naming);
  std::vector<std::string> inputs;
  for (const Job& j : jobs) inputs.push_back(j.input);
  return for_each_file(inputs, [&](std::size_t i) { one(jobs[i]); });
}

std::string other_ways(const Job& job) {
  return job.derived ? "name another output (-o NAME, --output-dir DIR, or -c for standard output)"
                     : "name another output";
}

void add_verbosity_flags(CLI::App* cmd, Verbosity& v) {
  cmd->add_flag("-v,--verbose", v.verbose, "A line per file on stderr: sizes, ratio, bits per vertex, time");
  cmd->add_flag("-q,--quiet", v.quiet, "No notes or warnings, only errors");
}

}  // namespace qsp::cli
