// `qsp reorder --like REF IN -o OUT`: IN's positions in REF's vertex order, with REF's face order and
// first corners, so data made per vertex / face / corner of REF applies to OUT unchanged; IN's texture
// coordinates, normals, colours, face labels, tags and kept lines go with their vertices, faces and corners.
// Exit codes as the other subcommands: 1 when IN is not isomorphic to REF (or is invalid). The work is
// the library's: match() and reorder_like() (qsp/match.h), or for polygon meshes (faces of any degree,
// non-manifold pieces, or IN with attributes) match_polygons() and reorder_polygons_like(), written as
// OBJ, OFF, PLY or a .qsp that keeps the order. All-quad meshes are matched as quads either way.
#include <sys/stat.h>

#include <cstdio>
#include <optional>
#include <string>
#include <tuple>

#include "commands.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/match.h"
#include "shared.h"

namespace qsp::cli {
namespace {

struct ReorderOptions {
  std::string ref, input, output;
  std::string format;  // --format for standard input
  Centering centering = Centering::kComponent;
  bool force = false;
  bool sync = false;
  DropOptions drop;
  bool float32 = false;       // round coordinates float32 does not hold instead of keeping float64
  bool prefer_order = false;  // MatchOptions::prefer_order
  bool allow_mirror = false;  // MatchOptions::mirror: kAccept, else kHint
};

MatchOptions match_options(const ReorderOptions& o) {
  MatchOptions mo;
  mo.centering = o.centering;
  mo.prefer_order = o.prefer_order;
  mo.mirror = o.allow_mirror ? Mirror::kAccept : Mirror::kHint;
  return mo;
}

// What reorder says when IN is not REF's topology (exit 1), or warns about when it is.
int not_isomorphic(const ReorderOptions& o, const std::string& reason, bool mirror_would_match) {
  const std::string hint = mirror_would_match ? mirror_hint(o.ref, o.input) : "";
  std::fprintf(stderr, "qsp: %s is not isomorphic to %s: %s%s\n", o.input.c_str(), o.ref.c_str(),
               name_meshes(reason, o.ref, o.input).c_str(), hint.c_str());
  return exit_code(Outcome::kDiffer);
}

void say_mirrored(const ReorderOptions& o) {
  std::fprintf(stderr, "qsp: %s is %s with every face reversed (--allow-mirror): OUT takes %s's faces\n",
               o.input.c_str(), o.ref.c_str(), o.ref.c_str());
}

// The warning where the quad way's choice among a symmetric mesh's isomorphisms had a rival.
void say_ambiguous(const ReorderOptions& o, const MatchResult& r) {
  if (r.ambiguous)
    std::fprintf(stderr, "qsp: warning: %s: the correspondence is ambiguous (symmetric mesh, %s)\n",
                 o.input.c_str(), r.exhaustive ? "equally near isomorphisms" : "search capped");
}

// REF or IN is a polygon mesh (or non-manifold quads), or IN carries more than positions and faces:
// match_polygons (or match_as_quads) and reorder_polygons_like.
int run_polygons(const ReorderOptions& o, MeshFormat format, const PolygonInput& ref, const PolygonInput& in,
                 const PolygonMesh& in_mesh) {
  const PolygonMesh ref_mesh = polygons_of(ref);
  PolygonMatchResult r;
  if (const std::optional<MatchResult> q = match_as_quads(ref_mesh, in_mesh, match_options(o))) {
    if (!q->isomorphic) return not_isomorphic(o, q->reason, q->mirror_would_match);
    say_ambiguous(o, *q);
    r.isomorphic = true;
    r.mirrored = q->mirrored;
    r.vertex = q->vertex;
    r.face = q->face;
    r.rotation.assign(q->rotation.begin(), q->rotation.end());
  } else {
    r = match_polygons(prepare_polygon_located(ref_mesh, o.ref, ref.report),
                       prepare_polygon_located(in_mesh, o.input, in.report), match_options(o));
    if (!r.isomorphic) return not_isomorphic(o, r.reason, r.mirror_would_match);
    if (!r.unique && !r.same_positions && !r.snapped)
      std::fprintf(
          stderr,
          "qsp: warning: %s: the mesh may be symmetric: OUT follows one of its isomorphisms (the nearest "
          "is searched on all-quad meshes only)\n",
          o.input.c_str());
  }
  if (r.mirrored) say_mirrored(o);
  const PolygonMesh out = reorder_polygons_like(in_mesh, r);
  if (out.face_offsets != ref_mesh.face_offsets || out.corners != ref_mesh.corners)
    throw Error(ErrorCode::kInternal, "reorder: faces do not come out in REF's order");
  // OBJ cannot take a label away: a face without one after a face with one would be written first.
  if (format == MeshFormat::kObj)
    for (const auto& [labels, kind, drop] :
         {std::tuple{&out.objects, "object", "group"}, std::tuple{&out.groups, "group", "group"},
          std::tuple{&out.materials, "material", "material"},
          std::tuple{&out.smoothing, "smoothing group", "smoothing"}}) {
      bool labelled = false;
      for (std::size_t f = 0; f < labels->face.size(); ++f) {
        if (labels->face[f] != kInvalid) {
          labelled = true;
        } else if (labelled) {
          throw Error(ErrorCode::kUnsupported,
                      o.output + ": face " + std::to_string(f) + " in REF's order has no " + kind +
                          " but an earlier face has one, which OBJ cannot write in that order; write a .qsp "
                          "(it keeps the order), or pass --drop " +
                          drop);
        }
      }
    }
  const std::vector<std::string> comments = kept_comments(in.report, o.drop);
  std::string bytes;
  if (format == MeshFormat::kQsp) {  // the order kept, so decompressing gives REF's
    EncodeOptions eo;
    eo.keep_order = true;
    bytes = encode_polygons(out, eo);
    if (!comments.empty()) bytes = with_comments(bytes, comments);
  } else {
    Mesh mesh = from_polygon_mesh(out);
    mesh.comments = comments;
    qsp::WriteOptions w;
    w.ply_format = PlyFormat::kBinaryLittleEndian;
    bytes = write_mesh(mesh, format, w);
  }
  write_output(o.output, bytes, {o.force, false, "name another output (-o NAME)", o.sync});
  return exit_code(Outcome::kSuccess);
}

int run(const ReorderOptions& o) {
  const MeshFormat format = o.output == "-" ? MeshFormat::kObj : format_from_path(o.output);
  if (format != MeshFormat::kObj && format != MeshFormat::kOff && format != MeshFormat::kPly &&
      format != MeshFormat::kQsp)
    throw Error(ErrorCode::kUnsupported, o.output + ": can write .obj, .off, .ply or .qsp only");
  if (o.ref == "-" && o.input == "-")
    throw CLI::ValidationError("REF and IN cannot both be standard input (-)");
  check_outputs({o.ref, o.input}, {{o.output, "-o"}});

  const MeshFormat in_format = parse_format_option(o.format);
  // Only IN's data reaches OUT; REF contributes its order alone. IN keeps what a .qsp keeps, unless dropped.
  const unsigned keep = (kPolygonMeshCategories | kCategoryExtra) & ~o.drop.categories();
  const PolygonInput ref = read_polygon_input(o.ref, in_format, QspInput::kDecoded),
                     in = read_polygon_input(o.input, in_format, QspInput::kDecoded, keep);
  const ReadReport refusable = refusable_extra(in.report, keep);
  const std::string dropped =
      refuse_extra_data(o.input, refusable, "reorder", o.drop, false, kPolygonMeshCategories);
  // A mesh file with more than positions and faces (or coordinates float32 does not hold) was read by the
  // exact reader: not `quads`.
  if (!ref.quads || !in.quads) {
    PolygonMesh in_mesh = polygons_of(in);
    // A decoded .qsp carries what it holds: --drop applies here (a mesh file's reader took it).
    const std::string dropped_from_qsp = in.from_qsp ? drop_polygon_data(in_mesh, o.input, o.drop) : "";
    // Lines kept as text go to OBJ and .qsp only (OFF and PLY refuse them): no "keeping" note before that.
    const bool holds_lines = format == MeshFormat::kObj || format == MeshFormat::kQsp;
    check_kept_values(
        o.input, in, in_mesh,
        {"reorder", holds_lines ? "OUT has them before the vertices" : "", o.float32, false, false});
    for (std::size_t t = 0; t < in_mesh.tags.size(); ++t)
      if (tag_indices(in_mesh.tags[t].name) == TagIndices::kUnknown)
        throw Error(ErrorCode::kUnsupported,
                    o.input + ": tag " + std::to_string(t) + " ('" + in_mesh.tags[t].name +
                        "') indexes what qsp cannot renumber, so reorder cannot keep it: "
                        "pass --drop tag");
    const int rc = run_polygons(o, format, ref, in, in_mesh);
    std::fputs(dropped.c_str(), stderr);
    std::fputs(dropped_from_qsp.c_str(), stderr);
    return rc;
  }
  MatchInput pref, pin;
  try {
    pref = prepare_located(ref.mesh, o.ref, ref.report);
    pin = prepare_located(in.mesh, o.input, in.report);
  } catch (const Error& e) {
    // Quads only, but non-manifold or mis-oriented: cut apart as any polygon mesh is.
    if (!polygon_path_takes(e)) throw;
    const int rc = run_polygons(o, format, ref, in, polygons_of(in));
    std::fputs(dropped.c_str(), stderr);
    return rc;
  }
  const MatchResult r = match(pref, pin, match_options(o));
  if (!r.isomorphic) return not_isomorphic(o, r.reason, r.mirror_would_match);
  if (r.mirrored) say_mirrored(o);
  say_ambiguous(o, r);

  const QuadMesh out = reorder_like(in.mesh, r);
  if (out.quads != ref.mesh.quads)
    throw Error(ErrorCode::kInternal, "reorder: faces do not come out in REF's order");
  const std::vector<std::string> comments = kept_comments(in.report, o.drop);
  std::string bytes;
  if (format == MeshFormat::kQsp) {
    // Keep the order in the file, so decompressing gives REF's order.
    EncodeOptions eo;
    eo.keep_order = true;
    bytes = encode(out, eo);
    if (!comments.empty()) bytes = with_comments(bytes, comments);
  } else if (format == MeshFormat::kPly) {
    Mesh mesh = from_quad_mesh(out);
    mesh.comments = comments;
    qsp::WriteOptions w;
    w.ply_format = PlyFormat::kBinaryLittleEndian;
    bytes = write_ply_mesh(mesh, w);
  } else {
    bytes = format == MeshFormat::kOff ? write_off(out, comments) : write_obj(out, comments);
  }
  write_output(o.output, bytes, {o.force, false, "name another output (-o NAME)", o.sync});
  std::fputs(dropped.c_str(), stderr);
  return exit_code(Outcome::kSuccess);
}

}  // namespace

void register_reorder(CLI::App& app, int& rc) {
  auto opt = std::make_shared<ReorderOptions>();
  CLI::App* cmd =
      app.add_subcommand("reorder", "Write IN with REF's vertex and face order (IN isomorphic to REF)");
  cmd->add_option("--like", opt->ref, "Reference mesh whose order OUT takes")->required();
  cmd->add_option("IN", opt->input, "Mesh to reorder (.obj .off .ply .qsp)")->required();
  cmd->add_option("-o,--output", opt->output,
                  "Output .obj, .off, .ply or .qsp (keeps the order) (- = OBJ on stdout)")
      ->required();
  cmd->add_flag("-f,--force", opt->force, "Replace OUT if it exists (never an input)");
  add_sync_flag(cmd, opt->sync);
  add_format_option(cmd, opt->format);
  add_centering_option(cmd, opt->centering);
  cmd->add_flag("--allow-mirror", opt->allow_mirror,
                "Also accept IN mirrored or with flipped normals (every face reversed); OUT takes REF's "
                "faces, so its normals are REF's");
  cmd->add_flag("--prefer-order", opt->prefer_order,
                "For meshes exported in one vertex order: the isomorphism keeping most vertices at their own "
                "index (the identity where it is one), the nearest among those keeping as many");
  add_drop_options(cmd, opt->drop, "IN's ", kPolygonMeshCategories);
  cmd->add_flag("--float32", opt->float32,
                "Round IN's coordinates, texture coordinates, normals and colours with more digits than "
                "float32 holds to the nearest float32 instead of keeping them as float64 (needed beyond 17 "
                "significant digits)");
  cmd->callback([opt, &rc] { rc = run(*opt); });
}

}  // namespace qsp::cli
