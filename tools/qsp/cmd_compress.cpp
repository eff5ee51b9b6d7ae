// `qsp compress IN [OUT]`: mesh file -> .qsp (format-spec/qsp_format.md).
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <string>

#include "commands.h"
#include "load.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"

namespace qsp::cli {
namespace {

struct CompressOptions {
  std::string input;
  std::string output;        // positional OUT
  std::string output_flag;   // -o OUT
  std::string input_format;  // for standard input: obj, off
  bool force = false;
  std::uint32_t quantize = 0;
  bool keep_order = false;
  bool positions_only = false;
  std::string partition = "auto";  // or a PartitionMode name
  std::string compat;              // "2.1": only what format 2.1 readers decode
  int level = kDefaultLevel;       // -1 .. -9, --fast, --best
  unsigned threads = 0;            // 0: as the encoder sees fit
};

// True when `out` names the same existing file as `in` (by device and inode, so links and
// different spellings of one path are caught).
bool same_file(const std::string& in, const std::string& out) {
  if (in == "-" || out == "-") return false;
  struct stat a {
  }, b{};
  if (::stat(in.c_str(), &a) != 0 || ::stat(out.c_str(), &b) != 0) return false;
  return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

void run(const CompressOptions& o) {
  if (!o.output.empty() && !o.output_flag.empty()) throw CLI::ValidationError("give OUT or -o OUT, not both");
  std::string out = !o.output_flag.empty() ? o.output_flag : o.output;
  if (out.empty()) out = o.input == "-" ? "-" : o.input + ".qsp";
  if (same_file(o.input, out))
    throw Error(ErrorCode::kIo, out + ": is the input file; refusing to write over it");
  if (out == "-" && ::isatty(STDOUT_FILENO)) {
    throw Error(ErrorCode::kIo,
                "-: refusing to write compressed data to a terminal (redirect it or give OUT)");
  }

  MeshFormat format = MeshFormat::kUnknown;
  if (!o.input_format.empty()) {
    format = format_from_path("x." + o.input_format);
    if (format == MeshFormat::kUnknown || format == MeshFormat::kQsp) {
      throw CLI::ValidationError("--format must be obj, off or ply");
    }
  } else if (o.input == "-") {
    format = MeshFormat::kObj;
  }
  ReadReport report;
  QuadMesh mesh = read_mesh_file(o.input, &report, format);
  if (report.has_extra_data()) {
    if (!o.positions_only) {
      throw Error(ErrorCode::kUnsupported,
                  o.input + ": has " + report.describe_extra_data() +
                      ", which .qsp does not store; pass --positions-only to drop them");
    }
    std::fprintf(stderr, "qsp: %s: dropped %s (--positions-only)\n", o.input.c_str(),
                 report.describe_extra_data().c_str());
  }
  EncodeOptions eo;
  eo.quantize_bits = o.quantize;
  eo.keep_order = o.keep_order;
  eo.level = o.level;
  eo.threads = o.threads;
  if (o.partition != "auto") {
    PartitionMode mode = PartitionMode::kMotorcycle;
    parse_partition_mode(o.partition, mode);  // CLI11 checked the name
    eo.partition = mode;
  }
  if (o.compat == "2.1") eo.geometry_shapes = false;  // geometry revisions 4 and 5 only
  std::string bytes;
  try {
    bytes = encode(mesh, eo);
  } catch (const Error& e) {
    rethrow_located(e, o.input, report);  // topology errors name a face: say file:line
  }
  write_file_atomic(out, bytes, o.force);
}

}  // namespace

void register_compress(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<CompressOptions>();
  CLI::App* sub = app.add_subcommand("compress", "Compress a quad mesh (.obj, .off, .ply) into a .qsp file");
  sub->add_option("IN", opt->input, "Input mesh, or - for standard input (OBJ unless --format)")->required();
  sub->add_option("OUT", opt->output, "Output file (default: IN.qsp; - for standard output)");
  sub->add_option("-o,--output", opt->output_flag, "Output file (same as OUT)");
  sub->add_option("--format", opt->input_format, "Format of standard input: obj, off or ply");
  sub->add_option("--partition", opt->partition,
                  "Structured partition to store (all canonical): auto (default: the level decides; "
                  "levels 8 and 9 keep the smallest file of the three), motorcycle, greedy or merge")
      ->check(CLI::IsMember({"auto", "motorcycle", "greedy", "merge"}));
  sub->add_flag("-f,--force", opt->force, "Replace OUT if it exists (never the input)");
  sub->add_option("--quantize", opt->quantize,
                  "Lossy: quantize positions to BITS bits over the bounding box (1-30)")
      ->check(CLI::Range(1, 30));
  sub->add_flag("--keep-order", opt->keep_order, "Also store the vertex order, face order and first corners");
  sub->add_flag("--positions-only", opt->positions_only,
                "Drop texture coordinates, normals, groups, materials and tags instead of refusing");
  sub->add_option("--compat", opt->compat,
                  "2.1: write only what qsp format 2.1 readers decode (no geometry coding revision 6; "
                  "files of small meshes 1-2% larger)")
      ->check(CLI::IsMember({"2.1"}));
  // gzip's and zstd's spelling: -1 fastest .. -9 smallest, --fast = -1, --best = -9.
  for (int l = kMinLevel; l <= kMaxLevel; ++l) {
    const std::string name = "-" + std::to_string(l);
    sub->add_flag_callback(
        name, [opt, l] { opt->level = l; }, "Level " + std::to_string(l) + ": " + level_description(l));
  }
  sub->add_flag_callback(
      "--fast", [opt] { opt->level = kMinLevel; }, "Same as -1");
  sub->add_flag_callback(
      "--best", [opt] { opt->level = kMaxLevel; }, "Same as -9");
  sub->add_option("--threads", opt->threads, "Threads to use (default 0: up to two; 1: one)");
  sub->callback([opt, &exit_code]() {
    run(*opt);
    exit_code = 0;
  });
}

}  // namespace qsp::cli
