// `qsp layout IN -o LAYOUT.obj [--patches OUT.obj|OUT.ply]`: the partition exported for other tools
// (qsp/layout_export.h).
#include <cstdio>
#include <string>

#include "commands.h"
#include "partitioned.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/layout_export.h"
#include "shared.h"

namespace qsp::cli {
namespace {

struct LayoutOptions {
  std::string input, output, patches;
  std::string partition;  // "" = the input's default (see load_partitioned)
  std::string format;     // --format for standard input
  bool force = false;
  bool sync = false;
};

void run(const LayoutOptions& o) {
  if (o.output.empty() && o.patches.empty())
    throw CLI::ValidationError("give -o LAYOUT.obj, --patches OUT, or both");
  if (!o.output.empty() && format_from_path(o.output) != MeshFormat::kObj)
    throw CLI::ValidationError("-o must name a .obj file, not '" + o.output + "'");
  const MeshFormat pf = o.patches.empty() ? MeshFormat::kUnknown : format_from_path(o.patches);
  if (!o.patches.empty() && pf != MeshFormat::kObj && pf != MeshFormat::kPly)
    throw CLI::ValidationError("--patches must name a .obj or .ply file, not '" + o.patches + "'");
  std::vector<Output> outputs;
  if (!o.output.empty()) outputs.push_back({o.output, "-o"});
  if (!o.patches.empty()) outputs.push_back({o.patches, "--patches"});
  check_outputs({o.input}, outputs);
  // Both outputs are checked before either is written, so a refusal leaves neither behind.
  const WriteOptions wo{o.force, false, "name another output", o.sync};
  refuse_existing(outputs, wo);
  const PartitionedMesh pm = load_partitioned(o.input, o.partition, parse_format_option(o.format));
  const std::string header = describe(o.input, pm);
  // Both outputs are exports for other tools, not the mesh kept: say so rather than refuse.
  if (!pm.rounding.empty())
    std::fprintf(stderr, "qsp: warning: %s; layout writes float32 positions\n", pm.rounding.c_str());
  if (!o.output.empty()) write_output(o.output, layout_obj(pm.mesh, pm.canonical, header), wo);
  if (!o.patches.empty()) {
    write_output(o.patches,
                 pf == MeshFormat::kPly ? patches_ply(pm.drawn, pm.view, header)
                                        : patches_obj(pm.drawn, pm.view, header),
                 wo);
  }
}

}  // namespace

void register_layout(CLI::App& app, int& rc) {
  auto opt = std::make_shared<LayoutOptions>();
  CLI::App* sub = app.add_subcommand(
      "layout",
      "Export the schematic partition as a polygon mesh, and the mesh with its faces tagged by patch");
  sub->add_option("IN", opt->input, "Mesh (.obj .off .ply) or .qsp file; - for standard input")->required();
  sub->add_option("-o,--output", opt->output,
                  "Layout OBJ: a face per patch over the schematic vertices, edge lengths in comments");
  sub->add_option("--patches", opt->patches,
                  "The mesh (positions only) with faces tagged by patch: .obj (groups patch_N, schematic "
                  "edges as l lines) or .ply (face properties patch, red, green, blue)");
  sub->add_option("--partition", opt->partition, kPartitionHelp)
      ->check(CLI::IsMember({"motorcycle", "greedy", "merge", "auto", "stored"}));
  add_format_option(sub, opt->format);
  sub->add_flag("-f,--force", opt->force, "Replace outputs that exist (never the input)");
  add_sync_flag(sub, opt->sync);
  sub->callback([opt, &rc] {
    run(*opt);
    rc = 0;
  });
}

}  // namespace qsp::cli
