// `qsp decompress IN... [OUT]`: .qsp files -> OBJ, OFF or PLY (by the output's extension), gzip's way
// (shared.h).
#include <sys/stat.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "commands.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/polymesh.h"
#include "shared.h"

namespace qsp::cli {
namespace {

struct DecompressOptions {
  FileArgs files;
  bool force = false;
  bool sync = false;
  Verbosity verbosity;
  DropOptions drop;  // what the written mesh leaves out (an output format that cannot hold it refuses it)
  std::uint64_t max_vertices = DecodeLimits{}.max_vertices;
  std::uint64_t max_faces = DecodeLimits{}.max_faces;
};

// IN minus ".qsp", plus ".obj" unless what is left already names a mesh format; "" without .qsp.
std::string beside(const std::string& in) {
  if (format_from_path(in) != MeshFormat::kQsp) return "";
  std::string base = in.substr(0, in.size() - 4);
  MeshFormat f = format_from_path(base);
  return f == MeshFormat::kObj || f == MeshFormat::kOff || f == MeshFormat::kPly ? base : base + ".obj";
}

// OBJ or OFF text of a decoded mesh: a quad mesh's as it always was, any other (and PLY, binary little
// endian as scanners and Draco write it) through the Mesh writers. `comments` (the file's leading comment
// block) first.
std::string mesh_text(PolygonMesh m, MeshFormat format, const std::vector<std::string>& comments) {
  bool quads = true;
  for (std::size_t f = 0; f < m.face_count(); ++f)
    quads = quads && m.face_offsets[f + 1] - m.face_offsets[f] == 4;
  if (format != MeshFormat::kPly && quads && m.bare()) {
    const QuadMesh q{std::move(m.positions), std::move(m.corners)};
    return format == MeshFormat::kOff ? write_off(q, comments) : write_obj(q, comments);
  }
  Mesh out = from_polygon_mesh(std::move(m));
  out.comments = comments;
  // The file's statement order (--keep-order) holds no comments: the leading block goes first.
  if (!out.statements.empty() && !comments.empty())
    out.statements.insert(out.statements.begin(),
                          Statement{ObjStatement::kComment, static_cast<std::uint32_t>(comments.size())});
  if (format == MeshFormat::kPly) {
    qsp::WriteOptions w;
    w.ply_format = PlyFormat::kBinaryLittleEndian;
    return write_ply_mesh(out, w);
  }
  return format == MeshFormat::kOff ? write_off_mesh(out) : write_obj_mesh(out);
}

void decompress_one(const Job& job, const DecompressOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  if (job.output.empty())
    throw Error(ErrorCode::kUnsupported, job.input +
                                             ": does not end in .qsp, so no output name can be made from it; "
                                             "give -o NAME.obj or -c");
  const MeshFormat format = job.output == "-" ? MeshFormat::kObj : format_from_path(job.output);
  if (format != MeshFormat::kObj && format != MeshFormat::kOff && format != MeshFormat::kPly)
    throw Error(ErrorCode::kUnsupported, job.output + ": can write .obj, .off or .ply only");
  struct stat st {};
  if (job.derived && !o.force && ::lstat(job.output.c_str(), &st) == 0)
    // x.obj.qsp -> x.obj is most likely the very mesh it came from, and the text written back differs
    // from it byte for byte (number formatting, and the canonical order unless --keep-order).
    throw Error(ErrorCode::kIo,
                job.output + ": already exists (perhaps the mesh " + job.input +
                    " was made from; decompress writes its own text, not the original bytes); "
                    "pass -f to replace it, or " +
                    other_ways(job));

  const std::string bytes = read_file_bytes(job.input);
  DecodeLimits limits;
  limits.max_vertices = o.max_vertices;
  limits.max_faces = o.max_faces;
  PolygonMesh mesh;
  try {
    mesh = decode_polygons(bytes, limits);
  } catch (const Error& e) {
    throw Error(e.code(), job.input + ": " + e.what());
  }
  std::vector<std::string> comments = comments_named(bytes, job.input);
  const std::string dropped = drop_polygon_data(mesh, job.input, o.drop, &comments);
  const std::size_t vertices = mesh.vertex_count(), faces = mesh.face_count();
  std::string text;
  try {
    text = mesh_text(std::move(mesh), format, comments);
  } catch (const Error& e) {
    // The writers' refusals name each kind with the --drop that drops it (decompress takes it too);
    // the other way out is the format that holds most: OBJ (per-corner values, labels, tags, kept
    // lines), or for an OBJ's refusal PLY (properties, face colours).
    const std::string base = job.output.substr(0, job.output.rfind('.'));
    const std::string other =
        format == MeshFormat::kObj ? "PLY: -o " + base + ".ply" : "OBJ: -o " + base + ".obj";
    throw Error(e.code(), job.input + " -> " + job.output + ": " + e.what() +
                              (e.code() == ErrorCode::kUnsupported ? " (try " + other + ")" : ""));
  }
  write_output(job.output, text, {o.force, o.verbosity.quiet, other_ways(job), o.sync});
  if (!o.verbosity.quiet) std::fputs(dropped.c_str(), stderr);
  if (o.verbosity.verbose && !o.verbosity.quiet) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const FileInfo info = inspect(bytes, limits);
    const int bits = info.quantize_bits;
    const std::string kind = bits > 0 ? "quantized " + std::to_string(bits) + " bits" : "lossless";
    std::fprintf(stderr, "qsp: %s -> %s: %zu -> %zu bytes, %zu vertices, %zu faces, %s, %s order, %.3f s\n",
                 job.input.c_str(), job.output.c_str(), bytes.size(), text.size(), vertices, faces,
                 kind.c_str(), info.keep_order ? "original" : "canonical", seconds);
  }
}

void run(const DecompressOptions& o, int& rc) {
  OutputNaming naming;
  naming.is_output_name = [](const std::string& p) {
    const MeshFormat f = format_from_path(p);
    return f == MeshFormat::kObj || f == MeshFormat::kOff || f == MeshFormat::kPly;
  };
  naming.beside = beside;
  naming.rule = "must end in .obj, .off or .ply";
  naming.verb = "decompress";
  naming.stdin_name = "stdin.obj";
  rc = run_jobs(o.files, naming, [&](const Job& job) { decompress_one(job, o); });
}

}  // namespace

void register_decompress(CLI::App& app, int& rc) {
  auto opt = std::make_shared<DecompressOptions>();
  CLI::App* sub = app.add_subcommand("decompress", "Decompress .qsp files into meshes (.obj, .off or .ply)");
  add_file_args(sub, opt->files,
                "Input .qsp files (IN without .qsp, .obj added if needed, is written beside each)",
                "ending in .obj, .off or .ply (binary little endian)");
  sub->add_flag("-f,--force", opt->force, "Replace outputs that exist (never an input)");
  add_sync_flag(sub, opt->sync);
  add_verbosity_flags(sub, opt->verbosity);
  add_drop_options(
      sub, opt->drop, "the written mesh's ", kPolygonMeshCategories,
      "an output format that cannot hold a kind the file has (OFF: texture coordinates and normals per "
      "corner, groups, materials, smoothing, tags, extra; PLY: most of those too) is refused unless it "
      "is dropped");
  sub->add_option("--max-vertices", opt->max_vertices, "Refuse files declaring more vertices (default 2^26)");
  sub->add_option("--max-faces", opt->max_faces, "Refuse files declaring more faces (default 2^26)");
  sub->callback([opt, &rc]() { run(*opt, rc); });
}

}  // namespace qsp::cli
