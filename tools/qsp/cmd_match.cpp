// `qsp match A B [-o MAP] [--faces FACEMAP]`: seed-free isomorphism between two quad meshes.
// Exit codes differ from the other subcommands on purpose (like cmp/diff): 0 isomorphic, 1 not
// isomorphic, 2 usage or invalid input mesh, 3 I/O, 4 internal; so "1" never means "broken input".
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <thread>

#include "commands.h"
#include "load.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/match.h"

namespace qsp::cli {
namespace {

struct MatchCliOptions {
  std::string a, b;
  std::string map;       // -o: vertex map
  std::string face_map;  // --faces
  std::string centering = "component";
  std::uint32_t max_evaluations = MatchOptions{}.max_full_evaluations;
  bool force = false;
  bool quiet = false;
};

Centering parse_centering(const std::string& s) {
  if (s == "component") return Centering::kComponent;
  if (s == "mesh") return Centering::kMesh;
  return Centering::kNone;  // CLI11 has checked it is one of the three
}

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

std::string count_text(std::uint64_t n) {
  if (n == UINT64_MAX) return "at least 18446744073709551615 isomorphisms";
  return std::to_string(n) + (n == 1 ? " isomorphism" : " isomorphisms");
}

// Reads a mesh file, or a .qsp decoded in full (vertices numbered as `qsp decompress` writes them),
// and prepares it for matching. Topology errors name the file and line, as load_mesh's do.
MatchInput read_and_prepare(const std::string& path) {
  ReadReport report;
  QuadMesh mesh = read_mesh_or_qsp(path, report);
  try {
    return prepare_match(std::move(mesh));
  } catch (const Error& e) {
    rethrow_located(e, path, report);
  }
}

// A and B side by side: reading and preparing are nearly all of a match's time. A's error wins.
void prepare_both(const std::string& pa, const std::string& pb, MatchInput& a, MatchInput& b) {
  std::exception_ptr failed;
  std::thread worker([&] {
    try {
      b = read_and_prepare(pb);
    } catch (...) {
      failed = std::current_exception();
    }
  });
  try {
    a = read_and_prepare(pa);
  } catch (...) {
    worker.join();
    throw;
  }
  worker.join();
  if (failed) std::rethrow_exception(failed);
}

int run(const MatchCliOptions& o) {
  MatchInput a, b;
  prepare_both(o.a, o.b, a, b);
  MatchOptions mo;
  mo.centering = parse_centering(o.centering);
  mo.max_full_evaluations = o.max_evaluations;
  const MatchResult r = match(a, b, mo);
  // The report goes to stdout unless a map does.
  std::FILE* report = (o.map == "-" || o.face_map == "-") ? stderr : stdout;
  if (!r.isomorphic) {
    if (!o.quiet) std::fprintf(report, "not isomorphic: %s\n", r.reason.c_str());
    return 1;
  }
  if (!o.map.empty()) write_file_atomic(o.map, vertex_map_text(r), o.force);
  if (!o.face_map.empty()) write_file_atomic(o.face_map, face_map_text(r), o.force);
  if (!o.quiet) {
    const double rms = r.vertex.empty() ? 0.0 : std::sqrt(r.cost / double(r.vertex.size()));
    std::fprintf(report, "isomorphic: %s; chose the nearest, rms distance %.6g",
                 count_text(r.isomorphisms).c_str(), rms);
    if (r.ambiguous) std::fprintf(report, "; ambiguous: another isomorphism is as near");
    if (!r.exhaustive)
      std::fprintf(report, "; nearest not proven (search capped, or many equal components paired greedily)");
    std::fprintf(report, "\n");
  }
  return 0;
}

}  // namespace

void register_match(CLI::App& app, int& exit_code) {
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
  cmd->add_flag("-f,--force", opt->force, "Replace MAP / FACEMAP if they exist");
  cmd->add_option(
         "--centering", opt->centering,
         "Positions compared to choose among symmetric isomorphisms: component (default), mesh, none")
      ->check(CLI::IsMember({"component", "mesh", "none"}));
  cmd->add_option("--max-evaluations", opt->max_evaluations,
                  "Per component, isomorphisms scored on all vertices at most (default 64)")
      ->check(CLI::Range(1u, 1u << 30));
  cmd->add_flag("-q,--quiet", opt->quiet, "Print nothing; the exit code says it");
  cmd->callback([opt, &exit_code] {
    try {
      exit_code = run(*opt);
    } catch (const Error& e) {
      // I/O (3) and internal (4) errors keep main's codes; an invalid mesh must not look like "not
      // isomorphic".
      if (e.code() == ErrorCode::kIo || e.code() == ErrorCode::kInternal) throw;
      std::fprintf(stderr, "qsp: error: %s\n", e.what());
      exit_code = 2;
    }
  });
}

}  // namespace qsp::cli
