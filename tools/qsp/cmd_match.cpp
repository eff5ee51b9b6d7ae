// `qsp match A B [-o MAP] [--faces FACEMAP]`: seed-free isomorphism between two quad meshes.
// Exit codes differ from the other subcommands on purpose (like cmp/diff): 0 isomorphic, 1 not
// isomorphic, 2 usage or invalid input mesh, 3 I/O, 4 internal; so "1" never means "broken input"
// (Answers::kCompare in main.cpp's table).
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <thread>
#include <utility>

#include "commands.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/match.h"
#include "shared.h"

namespace qsp::cli {
namespace {

struct MatchCliOptions {
  std::string a, b;
  std::string map;       // -o: vertex map
  std::string face_map;  // --faces
  std::string format;    // --format for standard input
  Centering centering = Centering::kComponent;
  std::uint32_t max_evaluations = MatchOptions{}.max_full_evaluations;
  bool force = false;
  bool sync = false;
  bool quiet = false;
  bool allow_mirror = false;  // also accept orientation-reversing isomorphisms
  bool prefer_order = false;  // MatchOptions::prefer_order
};

void append_number(std::string& out, std::uint64_t v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

// MAP: line i = B's vertex for A's vertex i.
std::string vertex_map_text(const MatchResult& r) {
  std::string out;
  out.reserve(r.vertex.size() * 8);
  for (std::uint32_t v : r.vertex) {
    append_number(out, v);
    out += '\n';
  }
  return out;
}

// FACEMAP: line f = "G R": A's face f is B's face G, A's corner c being B's corner (c + R) % 4.
std::string face_map_text(const MatchResult& r) {
  std::string out;
  out.reserve(r.face.size() * 10);
  for (std::size_t f = 0; f < r.face.size(); ++f) {
    append_number(out, r.face[f]);
    out += ' ';
    append_number(out, r.rotation[f]);
    out += '\n';
  }
  return out;
}

// Reads a mesh file, or a .qsp decoded in full (vertices numbered as `qsp decompress` writes them),
// and prepares it for matching. Topology errors name the file and line, as everywhere (prepare_located).
MatchInput read_and_prepare(const std::string& path, MeshFormat format) {
  ReadReport report;
  QuadMesh mesh = read_mesh_or_qsp(path, report, format);
  return prepare_located(std::move(mesh), path, report);
}

// A and B side by side: reading and preparing are nearly all of a match's time. A's error wins.
void prepare_both(const std::string& pa, const std::string& pb, MeshFormat format, MatchInput& a,
                  MatchInput& b) {
  std::exception_ptr failed;
  std::thread worker([&] {
    try {
      b = read_and_prepare(pb, format);
    } catch (...) {
      failed = std::current_exception();
    }
  });
  try {
    a = read_and_prepare(pa, format);
  } catch (...) {
    worker.join();
    throw;
  }
  worker.join();
  if (failed) std::rethrow_exception(failed);
}

int run(const MatchCliOptions& o) {
  if (o.a == "-" && o.b == "-") throw CLI::ValidationError("A and B cannot both be standard input (-)");
  std::vector<Output> outputs;
  if (!o.map.empty()) outputs.push_back({o.map, "-o"});
  if (!o.face_map.empty()) outputs.push_back({o.face_map, "--faces"});
  check_outputs({o.a, o.b}, outputs);
  MatchInput a, b;
  prepare_both(o.a, o.b, parse_format_option(o.format), a, b);
  MatchOptions mo;
  mo.centering = o.centering;
  mo.max_full_evaluations = o.max_evaluations;
  mo.prefer_order = o.prefer_order;
  // Orientation-reversing: accepted with --allow-mirror, else only named as the likely cause.
  mo.mirror = o.allow_mirror ? Mirror::kAccept : o.quiet ? Mirror::kNo : Mirror::kHint;
  MatchResult r = match(a, b, mo);
  if (r.mirror_would_match) r.reason += mirror_hint(o.a, o.b);
  // The report goes to stdout unless a map does.
  std::FILE* report = (o.map == "-" || o.face_map == "-") ? stderr : stdout;
  if (!r.isomorphic) {
    if (!o.quiet) std::fprintf(report, "not isomorphic: %s\n", name_meshes(r.reason, o.a, o.b).c_str());
    return exit_code(Outcome::kDiffer, Answers::kCompare);
  }
  const WriteOptions wo{o.force, o.quiet, "name another output", o.sync};
  refuse_existing(outputs, wo);  // both maps or neither
  if (!o.map.empty()) write_output(o.map, vertex_map_text(r), wo);
  if (!o.face_map.empty()) write_output(o.face_map, face_map_text(r), wo);
  if (!o.quiet) {
    const double rms = r.vertex.empty() ? 0.0 : std::sqrt(r.cost / double(r.vertex.size()));
    std::string chose = "the nearest";
    if (o.prefer_order) {
      std::size_t moved = 0;
      for (std::size_t v = 0; v < r.vertex.size(); ++v) moved += r.vertex[v] != v;
      chose = "the one keeping most vertices at their index (" + std::to_string(moved) +
              " moved), then the nearest";
    }
    std::fprintf(
        report, "isomorphic%s: %s; chose %s, rms distance %.6g",
        r.mirrored
            ? " (orientation-reversing: every face of B reversed; FACEMAP corner c is B's corner (R-c)%4)"
            : "",
        (isomorphism_count_text(r) + (r.isomorphisms == 1 ? " isomorphism" : " isomorphisms")).c_str(),
        chose.c_str(), rms);
    if (r.ambiguous) std::fprintf(report, "; ambiguous: another isomorphism is as near");
    if (!r.exhaustive)
      std::fprintf(report, "; nearest not proven (search capped, or many equal components paired greedily)");
    std::fprintf(report, "\n");
  }
  return exit_code(Outcome::kSuccess, Answers::kCompare);
}

}  // namespace

void register_match(CLI::App& app, int& rc) {
  auto opt = std::make_shared<MatchCliOptions>();
  CLI::App* cmd = app.add_subcommand("match",
                                     "Find the vertex correspondence between two isomorphic quad meshes "
                                     "(exit 0 isomorphic, 1 not, 2+ error)");
  cmd->add_option("A", opt->a, "First mesh (.obj .off .ply .qsp)")->required();
  cmd->add_option("B", opt->b, "Second mesh")->required();
  cmd->add_option("-o,--output", opt->map,
                  "Write the vertex map: line i = B's vertex for A's vertex i (- = stdout)");
  cmd->add_option(
      "--faces", opt->face_map,
      "Write the face map: line f = \"G R\", A's face f is B's face G, corner c is B's corner (c+R)%4");
  cmd->add_flag("-f,--force", opt->force, "Replace MAP / FACEMAP if they exist (never an input)");
  add_sync_flag(cmd, opt->sync);
  add_format_option(cmd, opt->format);
  add_centering_option(cmd, opt->centering);
  cmd->add_option("--max-evaluations", opt->max_evaluations,
                  "Per component, isomorphisms scored on all vertices at most (default 64)")
      ->check(CLI::Range(1u, 1u << 30));
  cmd->add_flag("-q,--quiet", opt->quiet, "Print nothing; the exit code says it");
  cmd->add_flag(
      "--prefer-order", opt->prefer_order,
      "For meshes exported in one vertex order: the isomorphism keeping most vertices at their own index "
      "(the identity where it is one), the nearest among those keeping as many");
  cmd->add_flag("--allow-mirror", opt->allow_mirror,
                "Also accept orientation-reversing isomorphisms (B mirrored or with flipped normals) when no "
                "orientation-preserving one exists; the report says which kind was found");
  // An invalid mesh must not look like "not isomorphic": main maps errors through the kCompare column.
  cmd->callback([opt, &rc] { rc = run(*opt); });
}

}  // namespace qsp::cli
