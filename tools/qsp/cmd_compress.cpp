// `qsp compress IN... [OUT]`: mesh files -> .qsp (format-spec/qsp_format.md), gzip's way (shared.h).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "commands.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "shared.h"

namespace qsp::cli {
namespace {

struct CompressOptions {
  FileArgs files;
  std::string input_format;  // obj, off, ply; "" = by name, else detected
  bool force = false;
  bool sync = false;
  Verbosity verbosity;
  std::uint32_t quantize = 0;
  std::uint32_t quantize_uv = 0;
  std::uint32_t quantize_color = 0;
  std::uint32_t quantize_normal = 0;
  bool keep_order = false;
  DropOptions drop;
  bool float32 = false;                   // round coordinates float32 does not hold instead of refusing
  std::string partition = "auto";         // or a PartitionMode name
  int level = kDefaultLevel;              // -1 .. -9, --fast, --best
  std::vector<std::string> levels_given;  // each level flag as given, in order (-14 gives -1, -4)
  unsigned threads = 0;                   // 0: as the encoder sees fit
};

// Up to this many vertices a quantized file is also encoded losslessly to warn when quantizing does
// not pay, where the positions lie on a coarse decimal grid (on_coarse_grid); above it, or on a fine
// grid, only with --verbose or from level 5, whose search costs more than the check: at the fast
// default levels it would double the compress time.
constexpr std::size_t kSizeCheckVertices = 1024;
constexpr int kSizeCheckLevel = 5;

// Whether every axis's positions lie on a grid of k <= 6 decimals (each float the nearest to its value
// rounded to k decimals, as the lossless coder's decimal grids take them) at most 16 times finer than
// the quantization grid of `bits` over the axis's range (a few bits more per coordinate): only there can
// the lossless file be the smaller (integer CAD cages, cube_4, millimetre coordinates), so only there is
// it worth a second, lossless encode to say so (on a 917-vertex scan with 6 decimals it was more than
// half the run). A flat axis costs nothing either way.
bool on_coarse_grid(const std::vector<float>& positions, std::uint32_t bits) {
  for (std::size_t a = 0; a < 3 && positions.size() >= 3; ++a) {
    float lo = positions[a], hi = positions[a];
    for (std::size_t i = a; i < positions.size(); i += 3)
      lo = std::min(lo, positions[i]), hi = std::max(hi, positions[i]);
    if (lo == hi) continue;
    const double step = (double{hi} - lo) / ((std::uint64_t{1} << bits) - 1);
    bool found = false;
    for (int k = 0; k <= 6 && !found && std::pow(10.0, -k) >= step / 16; ++k) {
      const double scale = std::pow(10.0, k);
      found = true;
      for (std::size_t i = a; i < positions.size() && found; i += 3)
        found = static_cast<float>(std::nearbyint(double{positions[i]} * scale) / scale) == positions[i];
    }
    if (!found) return false;
  }
  return true;
}

// The partition `bytes` stores, for --verbose: the option, or for auto the mode whose file is the
// same bytes (the codec keeps the smallest; up to three more encodes, only when asked).
std::string stored_partition(const PolygonMesh& mesh, const EncodeOptions& eo, const std::string& bytes,
                             const std::string& option) {
  if (option != "auto") return option;
  if (!level_effort(eo.level, mesh.vertex_count()).all_partitions) return "motorcycle (auto)";
  for (PartitionMode m : {PartitionMode::kMotorcycle, PartitionMode::kGreedy, PartitionMode::kMerge}) {
    EncodeOptions one = eo;
    one.partition = m;
    if (encode_polygons(mesh, one) == bytes) return std::string(partition_mode_name(m)) + " (auto)";
  }
  return "auto";
}

EncodeOptions encode_options(const CompressOptions& o) {
  EncodeOptions eo;
  eo.quantize_bits = o.quantize;
  eo.quantize_texcoord_bits = o.quantize_uv;
  eo.quantize_color_bits = o.quantize_color;
  eo.quantize_normal_bits = o.quantize_normal;
  eo.keep_order = o.keep_order;
  eo.level = o.level;
  eo.threads = o.threads;
  if (o.partition != "auto") {
    PartitionMode mode = PartitionMode::kMotorcycle;
    parse_partition_mode(o.partition, mode);  // CLI11 checked the name
    eo.partition = mode;
  }
  return eo;
}

void compress_one(const Job& job, MeshFormat format, const CompressOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const std::string& in = job.input;
  const MeshFormat out_format = format_from_path(job.output);
  if (out_format == MeshFormat::kObj || out_format == MeshFormat::kOff || out_format == MeshFormat::kPly)
    throw Error(ErrorCode::kUnsupported, job.output +
                                             ": a compressed file must not take a mesh name; name it " +
                                             job.output + ".qsp (or any name ending in .qsp)");
  if (job.output == "-" && ::isatty(STDOUT_FILENO))
    throw Error(ErrorCode::kIo,
                "-: refusing to write compressed data to a terminal (redirect it, or give OUT)");

  // Extra data is kept too (lines kept as text, vertex weights, PLY properties and obj_info lines), unless
  // dropped.
  const unsigned keep = (kPolygonMeshCategories | kCategoryExtra) & ~o.drop.categories();
  PolygonInput input = read_polygon_input(in, format, QspInput::kRefused, keep);
  PolygonMesh mesh = polygons_of(std::move(input));
  const ReadReport& report = input.report;
  const bool quiet = o.verbosity.quiet;
  const ReadReport refusable = refusable_extra(report, keep);
  const std::string dropped = refuse_extra_data(in, refusable, ".qsp", o.drop, quiet, kPolygonMeshCategories);
  check_kept_values(
      in, input, mesh,
      {".qsp", "decompress writes them back before the vertices", o.float32, o.quantize != 0, quiet,
       (o.quantize_uv ? kCategoryUv : 0u) | (o.quantize_normal ? kCategoryNormal : 0u) |
           (o.quantize_color ? kCategoryColor : 0u)});
  if (mesh.face_count() == 0 && !quiet)
    std::fprintf(stderr, "qsp: warning: %s: has no faces (%zu vertices); writing an empty mesh\n", in.c_str(),
                 mesh.vertex_count());
  // Octahedral normals need a direction (the codec keeps them exact otherwise): say so.
  for (std::size_t i = 0; o.quantize_normal && !quiet && i + 2 < mesh.normals.size(); i += 3)
    if (mesh.normals[i] == 0 && mesh.normals[i + 1] == 0 && mesh.normals[i + 2] == 0) {
      std::fprintf(
          stderr,
          "qsp: warning: %s: normal %zu has zero length; keeping the normals exact (--quantize-normal "
          "needs a direction)\n",
          in.c_str(), i / 3 + 1);
      break;
    }
  EncodeOptions eo = encode_options(o);
  // A tag whose indices qsp cannot renumber (OpenSubdiv's vertexedit, edgeedit, faceedit) keeps the
  // original order, as --keep-order does.
  for (const SubdivisionTag& t : mesh.tags) {
    if (eo.keep_order || tag_indices(t.name) != TagIndices::kUnknown) continue;
    eo.keep_order = true;
    if (!quiet)
      std::fprintf(stderr,
                   "qsp: %s: keeping the original order (as --keep-order): tag '%s' indexes what qsp "
                   "cannot renumber\n",
                   in.c_str(), t.name.c_str());
  }
  std::string bytes;
  std::uint64_t lossless_size = 0;
  try {
    bytes = encode_polygons(mesh, eo);
    if (o.quantize && !quiet &&
        ((mesh.vertex_count() <= kSizeCheckVertices && on_coarse_grid(mesh.positions, o.quantize)) ||
         o.level >= kSizeCheckLevel || o.verbosity.verbose)) {
      EncodeOptions exact = eo;
      exact.quantize_bits = 0;
      lossless_size = encode_polygons(mesh, exact).size();
    }
  } catch (const Error& e) {
    rethrow_located(e, in, report);  // topology errors name a face: say file:line
  }
  const std::vector<std::string> comments = kept_comments(report, o.drop);
  const std::string file = comments.empty() ? bytes : with_comments(bytes, comments);
  if (lossless_size) lossless_size += file.size() - bytes.size();  // both with the comments
  write_output(job.output, file, {o.force, quiet, other_ways(job), o.sync});
  std::fputs(dropped.c_str(), stderr);
  if (lossless_size && file.size() >= lossless_size)
    std::fprintf(stderr,
                 "qsp: warning: %s: at --quantize %u the file is %zu bytes, not smaller than lossless (%llu "
                 "bytes): positions are probably on a coarser grid already; drop --quantize\n",
                 in.c_str(), o.quantize, file.size(), (unsigned long long)lossless_size);
  if (o.verbosity.verbose && !quiet) {
    std::error_code ec;
    const auto in_size = in == "-" ? 0 : std::filesystem::file_size(in, ec);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double v = mesh.vertex_count() ? double(mesh.vertex_count()) : 1.0;
    std::string kind = o.quantize ? "quantized " + std::to_string(o.quantize) + " bits" : "lossless";
    if (lossless_size) kind += " (lossless " + std::to_string(lossless_size) + ")";
    std::fprintf(stderr, "qsp: %s -> %s: %llu -> %zu bytes", in.c_str(), job.output.c_str(),
                 (unsigned long long)(ec ? 0 : in_size), file.size());
    if (!ec && in_size) std::fprintf(stderr, " (%.2fx smaller)", double(in_size) / double(file.size()));
    std::fprintf(stderr, ", %.2f bits/vertex, %s%s, level %d, partition %s, %.3f s\n", 8.0 * file.size() / v,
                 kind.c_str(), o.keep_order ? ", order kept" : "", o.level,
                 stored_partition(mesh, eo, bytes, o.partition).c_str(), seconds);
  }
}

void run(const CompressOptions& o, int& rc) {
  // zstd's -19 is level 19 and -q14 reads as "quantize 14"; here both are several one-digit flags, which
  // would silently mean the last one.
  if (o.levels_given.size() > 1) {
    std::string flags, digits;
    for (const std::string& f : o.levels_given) {
      (flags += flags.empty() ? "" : " ") += f;
      digits += f.size() == 2 ? f.substr(1) : "";
    }
    const bool bits = digits.size() == o.levels_given.size() && std::stoi(digits) <= 30;
    throw Error(
        ErrorCode::kUsage,
        "compress: " + std::to_string(o.levels_given.size()) + " levels given (" +
            (digits.size() == o.levels_given.size() ? "-" + digits + " is " : std::string()) + flags +
            "); give one, -1 to -9 (or --fast, --best)" +
            (bits ? "; positions on a " + digits + "-bit grid are --quantize " + digits : std::string()));
  }
  const MeshFormat format = parse_format_option(o.input_format);
  OutputNaming naming;
  naming.is_output_name = [](const std::string& p) { return format_from_path(p) == MeshFormat::kQsp; };
  naming.beside = [](const std::string& in) { return in + ".qsp"; };
  naming.rule = "must end in .qsp";
  naming.verb = "compress";
  naming.stdin_name = "stdin.qsp";
  set_thread_limit(o.threads);  // the reader too, not only the encode
  rc = run_jobs(o.files, naming, [&](const Job& job) { compress_one(job, format, o); });
}

}  // namespace

void register_compress(CLI::App& app, int& rc) {
  auto opt = std::make_shared<CompressOptions>();
  CLI::App* sub = app.add_subcommand(
      "compress", "Compress meshes (.obj, .off, .ply; quad-dominant or any polygon mesh) into .qsp files");
  add_file_args(sub, opt->files, "Input meshes (IN.qsp is written beside each)", "ending in .qsp");
  add_format_option(sub, opt->input_format);
  sub->add_flag("-f,--force", opt->force, "Replace outputs that exist (never an input)");
  add_sync_flag(sub, opt->sync);
  add_verbosity_flags(sub, opt->verbosity);
  sub->add_option("--partition", opt->partition,
                  "Structured partition to store (all canonical): auto (default: the level decides; "
                  "levels 8 and 9 keep the smallest file of the three), motorcycle, greedy or merge")
      ->check(CLI::IsMember({"auto", "motorcycle", "greedy", "merge"}));
  sub->add_option("--quantize", opt->quantize,
                  "Lossy: quantize positions to BITS bits over the bounding box (1-30)")
      ->check(CLI::Range(1, 30));
  sub->add_option("--quantize-uv", opt->quantize_uv,
                  "Lossy: round texture coordinates to a grid of step 2^-BITS (1-24; 12 = 1/4096), "
                  "whatever their range, so a few far-off ones cost only themselves")
      ->check(CLI::Range(1, 24));
  sub->add_option("--quantize-color", opt->quantize_color,
                  "Lossy: round vertex and face colours to a grid of step 2^-BITS (1-24; 8 = 1/256); "
                  "colours already on a coarser decimal grid (PLY uchar) stay exact")
      ->check(CLI::Range(1, 24));
  sub->add_option(
         "--quantize-normal", opt->quantize_normal,
         "Lossy: store each normal as one of the (2^BITS - 1)^2 points of an octahedral grid (2-24; as "
         "Draco's -qn, 10 keeps each within 0.17 degrees, 16 within 0.003), unit length; a file with "
         "a normal of zero length keeps its normals exact")
      ->check(CLI::Range(2, 24));
  sub->add_flag("--keep-order", opt->keep_order, "Also store the vertex order, face order and first corners");
  add_drop_options(sub, opt->drop, "", kPolygonMeshCategories);
  sub->add_flag(
      "--float32", opt->float32,
      "Round coordinates, texture coordinates, normals and colours with more digits than float32 holds to "
      "the nearest float32 instead of keeping them as float64 (a smaller file, lossless for those float32 "
      "values); needed for text of more than 17 significant digits, which float64 does not hold");
  // gzip's and zstd's spelling: -1 fastest .. -9 smallest, --fast = -1, --best = -9.
  for (int l = kMinLevel; l <= kMaxLevel; ++l) {
    const std::string name = "-" + std::to_string(l);
    sub->add_flag_callback(
        name,
        [opt, l] {
          opt->level = l;
          opt->levels_given.push_back("-" + std::to_string(l));
        },
        "Level " + std::to_string(l) + ": " + level_description(l));
  }
  sub->add_flag_callback(
      "--fast",
      [opt] {
        opt->level = kMinLevel;
        opt->levels_given.push_back("--fast");
      },
      "Same as -1");
  sub->add_flag_callback(
      "--best",
      [opt] {
        opt->level = kMaxLevel;
        opt->levels_given.push_back("--best");
      },
      "Same as -9");
  sub->add_option("--threads", opt->threads,
                  "Threads to use (default 0: up to two; 1: one, reading included)");
  sub->callback([opt, &rc]() { run(*opt, rc); });
}

}  // namespace qsp::cli
