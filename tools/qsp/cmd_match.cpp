// `qsp match A B [-o MAP] [--faces FACEMAP]`: seed-free isomorphism between two quad meshes.
// Exit codes differ from the other subcommands on purpose (like cmp/diff): 0 isomorphic, 1 not
// isomorphic, 2 usage or invalid input mesh, 3 I/O, 4 internal; so "1" never means "broken input".
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <thread>
#include <utility>

#include "commands.h"
#include "files.h"
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
  std::string format;    // --format for standard input
  std::string centering = "component";
  std::uint32_t max_evaluations = MatchOptions{}.max_full_evaluations;
  bool force = false;
  bool quiet = false;
  bool allow_mirror = false;  // also accept orientation-reversing isomorphisms
  bool prefer_order = false;  // among equally near isomorphisms, the closest to the identity
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

// The number of isomorphisms, exact while it fits in 64 bits, else as a power of two and a decimal
// estimate: MatchResult::isomorphisms saturates, so the count is rebuilt from its factors (each
// component pair's symmetries, k! for k interchangeable components and for k unreferenced vertices).
std::string count_text(const MatchResult& r, const MatchInput& a) {
  const std::uint64_t n = r.isomorphisms;
  if (n != UINT64_MAX) return std::to_string(n) + (n == 1 ? " isomorphism" : " isomorphisms");
  double log2n = 0;
  const auto& comps = a.canonical.components;
  for (std::size_t i = 0; i < r.components.size(); ++i)
    log2n += std::log2(double(r.components[i].isomorphisms));
  const auto log2_factorial = [](std::size_t k) { return std::lgamma(double(k) + 1.0) / std::log(2.0); };
  for (std::size_t i = 0; i < comps.size();) {
    std::size_t j = i + 1;
    while (j < comps.size() && comps[j].code == comps[i].code) ++j;  // equal codes are adjacent
    log2n += log2_factorial(j - i);
    i = j;
  }
  log2n += log2_factorial(a.canonical.unreferenced.size());
  char buf[96];
  const double exponent = std::floor(log2n * std::log10(2.0));
  std::snprintf(buf, sizeof buf, "about 2^%.1f (%.1fe%.0f) isomorphisms", log2n,
                std::pow(10.0, log2n * std::log10(2.0) - exponent), exponent);
  return buf;
}

// The mesh with every face's corners reversed (v0 v3 v2 v1): orientation-reversing isomorphisms of
// the original are the orientation-preserving ones of this, with the same vertex and face numbers.
QuadMesh reversed(const QuadMesh& m) {
  QuadMesh out = m;
  for (std::size_t f = 0; f < out.face_count(); ++f) std::swap(out.quads[4 * f + 1], out.quads[4 * f + 3]);
  return out;
}

// A match of A against reversed(B.mesh), in B's numbering as the caller gave it, with rotations for
// B's own corners: A's corner c is B's corner (rotation - c) % 4.
MatchResult mirrored_match(const MatchInput& a, const MatchInput& b, const MatchOptions& mo) {
  MatchResult r = match(a, prepare_match(reversed(b.mesh)), mo);
  if (!r.isomorphic) return r;
  // reversed(b.mesh) keeps b.mesh's (possibly renumbered) order: map back as match() does.
  for (std::uint32_t& v : r.vertex)
    if (!b.vertex_old.empty()) v = b.vertex_old[v];
  for (std::size_t f = 0; f < r.face.size(); ++f) {
    if (!b.face_old.empty()) r.face[f] = b.face_old[r.face[f]];
    // Reversed corner k is B's corner (4 - k) % 4, k = (c + r) % 4.
    r.rotation[f] = static_cast<std::uint8_t>((4 - r.rotation[f]) & 3u);
  }
  return r;
}

// Reads a mesh file, or a .qsp decoded in full (vertices numbered as `qsp decompress` writes them),
// and prepares it for matching. Topology errors name the file and line, as load_mesh's do.
MatchInput read_and_prepare(const std::string& path, MeshFormat format) {
  ReadReport report;
  QuadMesh mesh = read_mesh_or_qsp(path, report, format);
  try {
    return prepare_match(std::move(mesh));
  } catch (const Error& e) {
    rethrow_located(e, path, report);
  }
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
  mo.centering = parse_centering(o.centering);
  mo.max_full_evaluations = o.max_evaluations;
  mo.prefer_order = o.prefer_order;
  MatchResult r = match(a, b, mo);
  bool mirror = false;
  // Reversing every face keeps the component sizes and extraordinary vertices: only a difference in
  // the schematic (the right-hand rule depends on orientation) or the code can be a mirror.
  const bool may_be_mirror = r.level == MatchLevel::kSchematic || r.level == MatchLevel::kCode;
  if (!r.isomorphic && may_be_mirror && (o.allow_mirror || !o.quiet)) {
    // Orientation-reversing: accepted with --allow-mirror, else only named as the likely cause.
    MatchResult m = mirrored_match(a, b, mo);
    if (m.isomorphic && o.allow_mirror) {
      r = std::move(m);
      mirror = true;
    } else if (m.isomorphic) {
      r.reason += "; but " + o.b + " is " + o.a +
                  " with every face reversed (mirrored, or turned inside out): pass --allow-mirror to accept "
                  "orientation-reversing matches";
    }
  }
  // The report goes to stdout unless a map does.
  std::FILE* report = (o.map == "-" || o.face_map == "-") ? stderr : stdout;
  if (!r.isomorphic) {
    if (!o.quiet) std::fprintf(report, "not isomorphic: %s\n", name_meshes(r.reason, o.a, o.b).c_str());
    return 1;
  }
  const WriteOptions wo{o.force, o.quiet, "name another output"};
  if (!o.map.empty()) write_output(o.map, vertex_map_text(r), wo);
  if (!o.face_map.empty()) write_output(o.face_map, face_map_text(r), wo);
  if (!o.quiet) {
    const double rms = r.vertex.empty() ? 0.0 : std::sqrt(r.cost / double(r.vertex.size()));
    std::fprintf(
        report, "isomorphic%s: %s; chose the nearest, rms distance %.6g",
        mirror ? " (orientation-reversing: every face of B reversed; FACEMAP corner c is B's corner (R-c)%4)"
               : "",
        count_text(r, a).c_str(), rms);
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
  cmd->add_flag("-f,--force", opt->force, "Replace MAP / FACEMAP if they exist (never an input)");
  add_format_option(cmd, opt->format);
  cmd->add_option(
         "--centering", opt->centering,
         "Positions compared to choose among symmetric isomorphisms: component (default), mesh, none")
      ->check(CLI::IsMember({"component", "mesh", "none"}));
  cmd->add_option("--max-evaluations", opt->max_evaluations,
                  "Per component, isomorphisms scored on all vertices at most (default 64)")
      ->check(CLI::Range(1u, 1u << 30));
  cmd->add_flag("-q,--quiet", opt->quiet, "Print nothing; the exit code says it");
  cmd->add_flag(
      "--prefer-order", opt->prefer_order,
      "Among equally near isomorphisms (symmetric parts), the one keeping most vertices at their own "
      "index (meshes exported in one order)");
  cmd->add_flag("--allow-mirror", opt->allow_mirror,
                "Also accept orientation-reversing isomorphisms (B mirrored or with flipped normals) when no "
                "orientation-preserving one exists; the report says which kind was found");
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
