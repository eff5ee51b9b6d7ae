// `qsp decompress IN [OUT]`: .qsp -> OBJ or OFF (by OUT's extension).
#include <sys/stat.h>

#include <string>

#include "commands.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"

namespace qsp::cli {
namespace {

struct DecompressOptions {
  std::string input;
  std::string output;       // positional OUT
  std::string output_flag;  // -o OUT
  bool force = false;
  std::uint64_t max_vertices = DecodeLimits{}.max_vertices;
  std::uint64_t max_faces = DecodeLimits{}.max_faces;
};

bool same_file(const std::string& in, const std::string& out) {
  if (in == "-" || out == "-") return false;
  struct stat a {
  }, b{};
  if (::stat(in.c_str(), &a) != 0 || ::stat(out.c_str(), &b) != 0) return false;
  return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

// IN minus ".qsp", plus ".obj" unless what is left already names a mesh format.
std::string default_output(const std::string& in) {
  if (in == "-") return "-";
  if (format_from_path(in) != MeshFormat::kQsp) {
    throw CLI::ValidationError(in + " does not end in .qsp: give OUT");
  }
  std::string base = in.substr(0, in.size() - 4);
  MeshFormat f = format_from_path(base);
  return f == MeshFormat::kObj || f == MeshFormat::kOff ? base : base + ".obj";
}

void run(const DecompressOptions& o) {
  if (!o.output.empty() && !o.output_flag.empty()) throw CLI::ValidationError("give OUT or -o OUT, not both");
  std::string out = !o.output_flag.empty() ? o.output_flag : o.output;
  if (out.empty()) out = default_output(o.input);
  MeshFormat format = out == "-" ? MeshFormat::kObj : format_from_path(out);
  if (format != MeshFormat::kObj && format != MeshFormat::kOff) {
    throw Error(ErrorCode::kUnsupported, out + ": can write .obj or .off only");
  }
  if (same_file(o.input, out))
    throw Error(ErrorCode::kIo, out + ": is the input file; refusing to write over it");

  const std::string bytes = read_file_bytes(o.input);
  DecodeLimits limits;
  limits.max_vertices = o.max_vertices;
  limits.max_faces = o.max_faces;
  QuadMesh mesh;
  try {
    mesh = decode(bytes, limits);
  } catch (const Error& e) {
    throw Error(e.code(), o.input + ": " + e.what());
  }
  write_file_atomic(out, format == MeshFormat::kOff ? write_off(mesh) : write_obj(mesh), o.force);
}

}  // namespace

void register_decompress(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<DecompressOptions>();
  CLI::App* sub = app.add_subcommand("decompress", "Decompress a .qsp file into a mesh (.obj or .off)");
  sub->add_option("IN", opt->input, "Input .qsp, or - for standard input")->required();
  sub->add_option("OUT", opt->output,
                  "Output mesh (default: IN without .qsp, .obj added if needed; - for stdout)");
  sub->add_option("-o,--output", opt->output_flag, "Output mesh (same as OUT)");
  sub->add_flag("-f,--force", opt->force, "Replace OUT if it exists (never the input)");
  sub->add_option("--max-vertices", opt->max_vertices, "Refuse files declaring more vertices (default 2^26)");
  sub->add_option("--max-faces", opt->max_faces, "Refuse files declaring more faces (default 2^26)");
  sub->callback([opt, &exit_code]() {
    run(*opt);
    exit_code = 0;
  });
}

}  // namespace qsp::cli
