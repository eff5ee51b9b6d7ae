// `qsp match A B [-o MAP] [--faces FACEMAP]`: seed-free isomorphism between two quad meshes, or two
// polygon meshes (any face degree, non-manifold and mis-oriented pieces: match_polygons).
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
std::string vertex_map_text(const std::vector<std::uint32_t>& vertex) {
  std::string out;
  out.reserve(vertex.size() * 8);
  for (std::uint32_t v : vertex) {
    append_number(out, v);
    out += '\n';
  }
  return out;
}

// FACEMAP: line f = "G R": A's face f is B's face G, A's corner c being B's corner (c + R) % d.
template <class Rotation>
std::string face_map_text(const std::vector<std::uint32_t>& face, const std::vector<Rotation>& rotation) {
  std::string out;
  out.reserve(face.size() * 10);
  for (std::size_t f = 0; f < face.size(); ++f) {
    append_number(out, face[f]);
    out += ' ';
    append_number(out, rotation[f]);
    out += '\n';
  }
  return out;
}

// One side of a match: a quad mesh prepared as today, or a polygon mesh (any face degree, non-manifold or
// mis-oriented pieces; qsp/match.h's polygon matching).
struct Side {
  bool polygon = false;
  QuadMesh quads;              // a quad mesh as read (kept: the other side may be a polygon mesh)
  MatchInput prepared;         // !polygon
  PolygonMesh mesh;            // polygon
  PolygonMatchInput polygons;  // prepared once both sides are read
};

// Reads a mesh file, or a .qsp decoded in full (vertices numbered as `qsp decompress` writes them),
// and prepares it for matching. Topology errors name the file and line, as everywhere (prepare_located).
// A quad mesh that build_adjacency refuses as non-manifold or mis-oriented goes the polygon way.
Side read_and_prepare(const std::string& path, MeshFormat format) {
  PolygonInput in = read_polygon_input(path, format, QspInput::kDecoded, 0, Coordinates::kRounded);
  Side side;
  if (in.quads) {
    try {
      side.prepared = prepare_located(in.mesh, path, in.report);
      side.quads = std::move(in.mesh);
      return side;
    } catch (const Error& e) {
      if (!polygon_path_takes(e)) throw;
    }
  }
  const ReadReport report = std::move(in.report);
  side.mesh = polygons_of(std::move(in));
  side.polygon = true;
  side.polygons = prepare_polygon_located(side.mesh, path, report);
  return side;
}

// A and B side by side: reading and preparing are nearly all of a match's time. A's error wins.
void prepare_both(const std::string& pa, const std::string& pb, MeshFormat format, Side& a, Side& b) {
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
  // A quad mesh against a polygon mesh: both the polygon way.
  for (Side* s : {&a, &b})
    if (!s->polygon && (a.polygon || b.polygon)) {
      s->polygon = true;
      s->mesh = polygon_mesh(s->quads);
      s->polygons = prepare_polygon_match(s->mesh);
    }
}

MatchOptions match_options(const MatchCliOptions& o) {
  MatchOptions mo;
  mo.centering = o.centering;
  mo.prefer_order = o.prefer_order;
  // Orientation-reversing: accepted with --allow-mirror, else only named as the likely cause.
  mo.mirror = o.allow_mirror ? Mirror::kAccept : o.quiet ? Mirror::kNo : Mirror::kHint;
  return mo;
}

// The report goes to stdout unless a map does.
std::FILE* report_stream(const MatchCliOptions& o) {
  return (o.map == "-" || o.face_map == "-") ? stderr : stdout;
}

// What both ways do with their result (MatchResult, PolygonMatchResult): say why the meshes differ
// (false), or write the maps (true).
template <class Result>
bool write_maps(const MatchCliOptions& o, Result& r, const std::vector<Output>& outputs) {
  if (r.mirror_would_match) r.reason += mirror_hint(o.a, o.b);
  if (!r.isomorphic) {
    if (!o.quiet)
      std::fprintf(report_stream(o), "not isomorphic: %s\n", name_meshes(r.reason, o.a, o.b).c_str());
    return false;
  }
  const WriteOptions wo{o.force, o.quiet, "name another output", o.sync};
  refuse_existing(outputs, wo);  // both maps or neither
  if (!o.map.empty()) write_output(o.map, vertex_map_text(r.vertex), wo);
  if (!o.face_map.empty()) write_output(o.face_map, face_map_text(r.face, r.rotation), wo);
  return true;
}

template <class Result>
double rms_distance(const Result& r) {
  return r.vertex.empty() ? 0.0 : std::sqrt(r.cost / double(r.vertex.size()));
}

// The polygon way: the same exit codes, maps and report lines, with rotations modulo each face's degree.
int run_polygons(const MatchCliOptions& o, const Side& a, const Side& b, const std::vector<Output>& outputs) {
  PolygonMatchResult r = match_polygons(a.polygons, b.polygons, match_options(o));
  if (!write_maps(o, r, outputs)) return exit_code(Outcome::kDiffer, Answers::kCompare);
  if (!o.quiet) {
    const char* which =
        r.identity         ? "the identity of indices (--prefer-order)"
        : r.unique         ? "the only isomorphism (every vertex told apart by its neighbourhood)"
        : r.same_positions ? "an isomorphism keeping every position (the mesh may have others)"
        : r.snapped ? "each symmetric vertex to the nearest of its candidates (the mesh may have other "
                      "isomorphisms; nearest not proven)"
                    : "one isomorphism (the mesh may be symmetric: the nearest is searched exhaustively "
                      "on all-quad meshes only)";
    std::fprintf(report_stream(o), "isomorphic%s: polygon meshes; %s, rms distance %.6g%s\n",
                 r.mirrored ? " (orientation-reversing: every face of B reversed; FACEMAP corner c is B's "
                              "corner (R-c)%d)"
                            : "",
                 which, rms_distance(r),
                 r.ambiguous ? "; ambiguous: unreferenced vertices as near in another pairing" : "");
  }
  return exit_code(Outcome::kSuccess, Answers::kCompare);
}

int run(const MatchCliOptions& o) {
  if (o.a == "-" && o.b == "-") throw CLI::ValidationError("A and B cannot both be standard input (-)");
  std::vector<Output> outputs;
  if (!o.map.empty()) outputs.push_back({o.map, "-o"});
  if (!o.face_map.empty()) outputs.push_back({o.face_map, "--faces"});
  check_outputs({o.a, o.b}, outputs);
  Side sa, sb;
  prepare_both(o.a, o.b, parse_format_option(o.format), sa, sb);
  MatchOptions mo = match_options(o);
  mo.max_full_evaluations = o.max_evaluations;
  MatchResult r;
  if (!sa.polygon) {
    r = match(sa.prepared, sb.prepared, mo);
  } else if (std::optional<MatchResult> q = match_as_quads(sa.mesh, sb.mesh, mo)) {
    r = std::move(*q);  // a polygon .qsp of quads
  } else {
    return run_polygons(o, sa, sb, outputs);
  }
  if (!write_maps(o, r, outputs)) return exit_code(Outcome::kDiffer, Answers::kCompare);
  if (!o.quiet) {
    std::FILE* report = report_stream(o);
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
        chose.c_str(), rms_distance(r));
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
  CLI::App* cmd = app.add_subcommand(
      "match",
      "Find the vertex correspondence between two isomorphic meshes (quads, or any polygons) "
      "(exit 0 isomorphic, 1 not, 2+ error)");
  cmd->add_option("A", opt->a, "First mesh (.obj .off .ply .qsp)")->required();
  cmd->add_option("B", opt->b, "Second mesh")->required();
  cmd->add_option("-o,--output", opt->map,
                  "Write the vertex map: line i = B's vertex for A's vertex i (- = stdout)");
  cmd->add_option(
      "--faces", opt->face_map,
      "Write the face map: line f = \"G R\", A's face f is B's face G, corner c is B's corner (c+R)%d, d "
      "its degree");
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
