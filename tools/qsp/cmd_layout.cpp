// `qsp layout IN -o LAYOUT.obj [--patches OUT.obj|OUT.ply]`: the partition exported for other tools
// (qsp/layout_export.h).
#include <filesystem>
#include <string>

#include "commands.h"
#include "partitioned.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/layout_export.h"

namespace qsp::cli {
namespace {

struct LayoutOptions {
  std::string input, output, patches;
  std::string partition;  // "" = the input's default (see load_partitioned)
  bool force = false;
};

void run(const LayoutOptions& o) {
  if (o.output.empty() && o.patches.empty())
    throw CLI::ValidationError("give -o LAYOUT.obj, --patches OUT, or both");
  if (!o.output.empty() && format_from_path(o.output) != MeshFormat::kObj)
    throw CLI::ValidationError("-o must name a .obj file, not '" + o.output + "'");
  const MeshFormat pf = o.patches.empty() ? MeshFormat::kUnknown : format_from_path(o.patches);
  if (!o.patches.empty() && pf != MeshFormat::kObj && pf != MeshFormat::kPly)
    throw CLI::ValidationError("--patches must name a .obj or .ply file, not '" + o.patches + "'");
  // Both outputs are checked before either is written, so a refusal leaves neither behind.
  for (const std::string& out : {o.output, o.patches})
    if (!o.force && !out.empty() && out != "-" && std::filesystem::exists(out))
      throw Error(ErrorCode::kIo, out + ": exists; pass -f to replace it");
  const PartitionedMesh pm = load_partitioned(o.input, o.partition);
  const std::string header = describe(o.input, pm);
  if (!o.output.empty()) write_file_atomic(o.output, layout_obj(pm.mesh, pm.canonical, header), o.force);
  if (!o.patches.empty()) {
    write_file_atomic(o.patches,
                      pf == MeshFormat::kPly ? patches_ply(pm.mesh, pm.view, header)
                                             : patches_obj(pm.mesh, pm.view, header),
                      o.force);
  }
}

}  // namespace

void register_layout(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<LayoutOptions>();
  CLI::App* sub = app.add_subcommand(
      "layout",
      "Export the schematic partition as a polygon mesh, and the mesh with its faces tagged by patch");
  sub->add_option("IN", opt->input, "Mesh (.obj .off .ply) or .qsp file")->required();
  sub->add_option("-o,--output", opt->output,
                  "Layout OBJ: a face per patch over the schematic vertices, edge lengths in comments");
  sub->add_option("--patches", opt->patches,
                  "The mesh (positions only) with faces tagged by patch: .obj (groups patch_N, schematic "
                  "edges as l lines) or .ply (face properties patch, red, green, blue)");
  sub->add_option("--partition", opt->partition, kPartitionHelp)
      ->check(CLI::IsMember({"motorcycle", "greedy", "merge", "auto", "stored"}));
  sub->add_flag("-f,--force", opt->force, "Replace outputs that exist");
  sub->callback([opt, &exit_code] {
    run(*opt);
    exit_code = 0;
  });
}

}  // namespace qsp::cli
