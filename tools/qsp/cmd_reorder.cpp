// `qsp reorder --like REF IN -o OUT`: IN's positions in REF's vertex order, with REF's face order and
// first corners, so data made per vertex / face / corner of REF applies to OUT unchanged.
// Exit codes as the other subcommands: 1 when IN is not isomorphic to REF (or is invalid).
#include <sys/stat.h>

#include <cstdio>
#include <string>

#include "commands.h"
#include "files.h"
#include "load.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/match.h"

namespace qsp::cli {
namespace {

struct ReorderOptions {
  std::string ref, input, output;
  std::string format;  // --format for standard input
  std::string centering = "component";
  bool force = false;
  bool positions_only = false;
  bool prefer_order = false;  // MatchOptions::prefer_order
};

struct Read {
  QuadMesh mesh;
  ReadReport report;
};

Read read_any(const std::string& path, MeshFormat format) {
  Read out;
  out.mesh = read_mesh_or_qsp(path, out.report, format);
  return out;
}

MatchInput prepare_located(const Read& r, const std::string& path) {
  try {
    return prepare_match(r.mesh);
  } catch (const Error& e) {
    rethrow_located(e, path, r.report);
  }
}

int run(const ReorderOptions& o) {
  const MeshFormat format = o.output == "-" ? MeshFormat::kObj : format_from_path(o.output);
  if (format != MeshFormat::kObj && format != MeshFormat::kOff && format != MeshFormat::kQsp)
    throw Error(ErrorCode::kUnsupported, o.output + ": can write .obj, .off or .qsp only");
  if (o.ref == "-" && o.input == "-")
    throw CLI::ValidationError("REF and IN cannot both be standard input (-)");
  check_outputs({o.ref, o.input}, {{o.output, "-o"}});

  const MeshFormat in_format = parse_format_option(o.format);
  const Read ref = read_any(o.ref, in_format);
  const Read in = read_any(o.input, in_format);
  // Only IN's data reaches OUT; REF contributes its order alone.
  if (in.report.has_extra_data()) {
    if (!o.positions_only)
      throw Error(ErrorCode::kUnsupported,
                  o.input + ": has " + in.report.describe_extra_data() +
                      ", which reorder does not carry over; pass --positions-only to drop them");
    std::fprintf(stderr, "qsp: %s: dropped %s (--positions-only)\n", o.input.c_str(),
                 in.report.describe_extra_data().c_str());
  }
  MatchOptions mo;
  mo.centering = o.centering == "mesh"   ? Centering::kMesh
                 : o.centering == "none" ? Centering::kNone
                                         : Centering::kComponent;
  mo.prefer_order = o.prefer_order;
  const MatchResult r = match(prepare_located(ref, o.ref), prepare_located(in, o.input), mo);
  if (!r.isomorphic) {
    std::fprintf(stderr, "qsp: %s is not isomorphic to %s: %s\n", o.input.c_str(), o.ref.c_str(),
                 name_meshes(r.reason, o.ref, o.input).c_str());
    return 1;
  }
  if (r.ambiguous)
    std::fprintf(stderr, "qsp: warning: %s: the correspondence is ambiguous (symmetric mesh, %s)\n",
                 o.input.c_str(), r.exhaustive ? "equally near isomorphisms" : "search capped");

  // OUT vertex i = IN vertex r.vertex[i]; OUT face f = IN face r.face[f] turned so that its corner c
  // is IN's corner (c + rotation) -- which is REF's face f, renumbered to OUT's vertices.
  const QuadMesh& src = in.mesh;
  const std::size_t nv = src.vertex_count(), nf = src.face_count();
  std::vector<std::uint32_t> out_of(nv);
  for (std::uint32_t i = 0; i < nv; ++i) out_of[r.vertex[i]] = i;
  QuadMesh out;
  out.positions.resize(3 * nv);
  for (std::size_t i = 0; i < nv; ++i)
    for (int k = 0; k < 3; ++k) out.positions[3 * i + k] = src.positions[3 * std::size_t(r.vertex[i]) + k];
  out.quads.resize(4 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (std::uint32_t c = 0; c < 4; ++c)
      out.quads[4 * f + c] = out_of[src.quads[4 * std::size_t(r.face[f]) + ((c + r.rotation[f]) & 3u)]];
  if (out.quads != ref.mesh.quads)
    throw Error(ErrorCode::kInternal, "reorder: faces do not come out in REF's order");
  std::string bytes;
  if (format == MeshFormat::kQsp) {
    // Keep the order in the file, so decompressing gives REF's order.
    EncodeOptions eo;
    eo.keep_order = true;
    bytes = encode(out, eo);
  } else {
    bytes = format == MeshFormat::kOff ? write_off(out) : write_obj(out);
  }
  write_output(o.output, bytes, {o.force, false, "name another output (-o NAME)"});
  return 0;
}

}  // namespace

void register_reorder(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<ReorderOptions>();
  CLI::App* cmd =
      app.add_subcommand("reorder", "Write IN with REF's vertex and face order (IN isomorphic to REF)");
  cmd->add_option("--like", opt->ref, "Reference mesh whose order OUT takes")->required();
  cmd->add_option("IN", opt->input, "Mesh to reorder (.obj .off .ply .qsp)")->required();
  cmd->add_option("-o,--output", opt->output,
                  "Output .obj, .off or .qsp (keeps the order) (- = OBJ on stdout)")
      ->required();
  cmd->add_flag("-f,--force", opt->force, "Replace OUT if it exists (never an input)");
  add_format_option(cmd, opt->format);
  cmd->add_option(
         "--centering", opt->centering,
         "Positions compared to choose among symmetric isomorphisms: component (default), mesh, none")
      ->check(CLI::IsMember({"component", "mesh", "none"}));
  cmd->add_flag("--prefer-order", opt->prefer_order,
                "Among equally near isomorphisms, the one keeping most vertices at their own index");
  cmd->add_flag("--positions-only", opt->positions_only,
                "Drop IN's texture coordinates, normals, groups, ... instead of refusing");
  cmd->callback([opt, &exit_code] { exit_code = run(*opt); });
}

}  // namespace qsp::cli
