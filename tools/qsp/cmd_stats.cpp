// `qsp stats FILE...`: the paper's Table-1 row per file (mesh counts, schematic counts, ratios). A
// polygon mesh's row is its quad submesh's, followed by its faces by degree and cut vertices.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "commands.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/match.h"
#include "qsp/mesh.h"
#include "qsp/partition.h"
#include "qsp/smaller.h"
#include "qsp/submesh.h"
#include "shared.h"

namespace qsp::cli {
namespace {

struct StatsOptions {
  std::vector<std::string> files;
  bool json = false;
  bool json_lines = false;
  std::string format;  // --format for standard input
  bool verbose = false;
  std::string partition = "motorcycle";  // a PartitionMode name, "auto" (as compress) or "all" (a row each)
  bool sizes = false;
};

struct Row {
  std::string file;
  std::string error;      // set (and nothing else) when the file could not be read
  std::string partition;  // mode name; shown in the table when not the default
  std::uint64_t vertices = 0, edges = 0, faces = 0, components = 0, extraordinary = 0, unreferenced = 0;
  std::uint64_t sx = 0, se = 0, patches = 0;
  bool has_bytes = false;  // a .qsp, or a mesh compressed in memory (--sizes)
  std::uint64_t total_bytes = 0, header_bytes = 0, connectivity_bytes = 0, geometry_bytes = 0,
                order_bytes = 0, texcoord_bytes = 0, label_bytes = 0, tag_bytes = 0, normal_bytes = 0,
                exact_bytes = 0, color_bytes = 0, property_bytes = 0, comment_bytes = 0, kept_line_bytes = 0,
                other_bytes = 0;  // the parts add up to the total
  bool keep_order = false;
  int quantize_bits = -1;  // 0 lossless, 1..30 quantized; -1 unknown
  int version_major = 0, version_minor = 0, level = 0;
  std::string geometry_tools;       // geometry_tool_names()
  const char* geometry_order = "";  // "patch" or "layout"
  struct Comp {
    const char* kind;
    std::uint64_t vertices, edges, faces, extraordinary, sx, se, patches;
    std::int64_t euler;
  };
  std::vector<Comp> comps;
  // A polygon mesh (any face degree, non-manifold pieces): the row is its quad submesh's, and these
  // are its faces by degree and what was cut apart (PolygonCounts, qsp/submesh.h).
  bool polygon = false;
  PolygonCounts polygons;
  std::uint64_t mesh_vertices = 0;  // the polygon mesh's own vertices (cut copies once, interior ones too)
  // Its polygons section (with bytes): the counts and region codes, the interior vertices' positions.
  std::uint64_t polygon_connectivity_bytes = 0, polygon_positions_bytes = 0, interior_positions = 0;
};

// Bits per vertex are over the mesh's vertices: a polygon mesh's own, not its quad submesh's (a
// triangle mesh has none of those).
double per_vertex(const Row& r) {
  const std::uint64_t n = r.polygon ? r.mesh_vertices : r.vertices;
  return n ? double(n) : 1.0;
}

// The polygons section's connectivity per face that is not a quad, in bits (0 without such faces).
double bits_per_non_quad(const Row& r) {
  const std::uint64_t n = std::uint64_t{r.polygons.triangles} + r.polygons.ngons;
  return n ? 8.0 * double(r.polygon_connectivity_bytes) / double(n) : 0.0;
}

void add_sizes(Row& r, const FileInfo& info) {
  r.has_bytes = true;
  r.total_bytes = info.total_bytes;
  r.header_bytes = info.header_bytes;
  r.connectivity_bytes = info.connectivity_bytes;
  r.geometry_bytes = info.geometry_bytes;
  r.order_bytes = info.order_bytes;
  r.texcoord_bytes = info.texcoord_bytes;
  r.label_bytes = info.label_bytes;
  r.tag_bytes = info.tag_bytes;
  r.normal_bytes = info.normal_bytes;
  r.exact_bytes = info.exact_bytes;
  r.color_bytes = info.color_bytes;
  r.property_bytes = info.property_bytes;
  r.comment_bytes = info.comment_bytes;
  r.kept_line_bytes = info.kept_line_bytes;
  r.other_bytes = info.other_bytes;
  r.keep_order = info.keep_order;
  r.quantize_bits = info.quantize_bits;
  r.version_major = info.version_major;
  r.version_minor = info.version_minor;
  r.level = info.level;
  r.geometry_tools = geometry_tool_names(info.geometry_tools);
  r.geometry_order = info.geometry_order == CodingOrder::kPatch ? "patch" : "layout";
  r.polygon_connectivity_bytes = info.polygon_connectivity_bytes;
  r.polygon_positions_bytes = info.polygon_positions_bytes;
  r.interior_positions = info.interior_positions;
}

// A .qsp's bytes: everything from inspect(), without decoding positions.
Row info_row(const std::string& file, const std::string& bytes, const char* partition) {
  FileInfo info;
  try {
    info = inspect(bytes);
  } catch (const Error& e) {
    throw Error(e.code(), file + ": " + e.what());  // as decompress says where
  }
  Row r;
  r.file = file;
  r.partition = partition;
  r.vertices = info.vertices;
  r.edges = info.edges;
  r.faces = info.faces;
  r.components = info.components.size();
  r.polygon = info.polygons;  // its polygons section (quads with texture coordinates are not)
  r.extraordinary = info.extraordinary;
  r.unreferenced = info.unreferenced;
  for (const auto& c : info.components) {
    const bool closed = c.kind == ComponentKind::kAnnulus || c.kind == ComponentKind::kTorus;
    // A .qsp does not store per-component edge or extraordinary counts; those columns read 0.
    r.comps.push_back({component_kind_name(c.kind), c.vertices, 0, c.faces, 0, c.schematic_vertices,
                       c.schematic_edges, closed ? 1u : c.patches, 0});
    // Totals as mesh_row counts them: an annulus or torus is one patch, as in every partition mode.
    r.sx += r.comps.back().sx;
    r.se += r.comps.back().se;
    r.patches += r.comps.back().patches;
  }
  add_sizes(r, info);
  return r;
}

Row mesh_row(const std::string& file, const LoadedMesh& loaded, PartitionMode mode) {
  const QuadMesh& mesh = loaded.mesh;
  const Adjacency& adj = loaded.adjacency;
  const Partition part = partition(adj, mode);
  const auto info = component_info(adj);
  Row r;
  r.file = file;
  r.partition = partition_mode_name(mode);
  r.vertices = mesh.vertex_count();
  r.faces = mesh.face_count();
  r.components = adj.component_count;
  r.unreferenced = part.unreferenced.size();
  for (std::uint32_t c = 0; c < adj.component_count; ++c) {
    const auto& p = part.components[c];
    const bool closed = p.kind == ComponentKind::kAnnulus || p.kind == ComponentKind::kTorus;
    Row::Comp k{component_kind_name(p.kind),
                info[c].vertices,
                info[c].edges,
                info[c].faces,
                info[c].extraordinary,
                closed ? 0 : p.schematic.vertex_count,
                closed ? 0 : p.schematic.edge_count(),
                closed ? 1 : p.schematic.patch_count(),
                info[c].euler()};
    r.edges += k.edges;
    r.extraordinary += k.extraordinary;
    r.sx += k.sx;
    r.se += k.se;
    r.patches += k.patches;
    r.comps.push_back(k);
  }
  return r;
}

double pct(std::uint64_t a, std::uint64_t b) { return b ? 100.0 * double(a) / double(b) : 0.0; }

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

// One object per row, an array unless `lines` (then one object per line); a file that failed is
// {"file": ..., "error": ...} in its place.
void print_json(const std::vector<Row>& rows, bool verbose, bool lines) {
  if (!lines) std::printf("[\n");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    const char* sep = lines || i + 1 == rows.size() ? "" : ",";
    if (!r.error.empty()) {
      std::printf("{\"file\": %s, \"error\": %s}%s\n", json_string(r.file).c_str(),
                  json_string(r.error).c_str(), sep);
      continue;
    }
    std::printf(
        "{\"file\": %s, \"partition\": \"%s\", \"mesh\": {\"vertices\": %llu, \"edges\": %llu, \"faces\": "
        "%llu, \"components\": %llu, "
        "\"extraordinary\": %llu, \"unreferenced\": %llu}, \"schematic\": {\"vertices\": %llu, \"edges\": "
        "%llu, "
        "\"patches\": %llu}, \"relative\": {\"vertices\": %.4f, \"edges\": %.4f}",
        json_string(r.file).c_str(), r.partition.c_str(), (unsigned long long)r.vertices,
        (unsigned long long)r.edges, (unsigned long long)r.faces, (unsigned long long)r.components,
        (unsigned long long)r.extraordinary, (unsigned long long)r.unreferenced, (unsigned long long)r.sx,
        (unsigned long long)r.se, (unsigned long long)r.patches, pct(r.sx, r.vertices), pct(r.se, r.edges));
    if (r.polygon) {
      const PolygonCounts& n = r.polygons;
      std::printf(
          ", \"polygons\": {\"quads\": %u, \"triangles\": %u, \"ngons\": %u, \"cut_vertices\": %u, "
          "\"cut_edges\": %u, \"extra_copies\": %u, \"vertices\": %llu}",
          n.quads, n.triangles, n.ngons, n.cut_vertices, n.cut_edges, n.extra_copies,
          (unsigned long long)r.mesh_vertices);
    }
    if (r.has_bytes) {
      const double v = per_vertex(r);
      if (r.polygon) {
        std::printf(
            ", \"polygons_section\": {\"connectivity\": %llu, \"positions\": %llu, "
            "\"connectivity_bits_per_non_quad_face\": %.4f, \"interior_positions_in_geometry\": %llu}",
            (unsigned long long)r.polygon_connectivity_bytes, (unsigned long long)r.polygon_positions_bytes,
            bits_per_non_quad(r), (unsigned long long)r.interior_positions);
      }
      std::printf(
          ", \"bytes\": {\"total\": %llu, \"header\": %llu, \"connectivity\": %llu, \"geometry\": %llu, "
          "\"order\": %llu, \"texcoords\": %llu, \"labels\": %llu, \"tags\": %llu, \"normals\": %llu, "
          "\"exact_positions\": %llu, \"colors\": %llu, \"properties\": %llu, \"comments\": %llu, "
          "\"kept_lines\": %llu, \"other\": %llu}, "
          "\"bits_per_vertex\": {\"total\": %.4f, \"connectivity\": %.4f, \"geometry\": %.4f}, "
          "\"format\": \"%d.%d\", \"level\": %d, \"geometry_coding\": {\"tools\": %s, \"order\": \"%s\"}, "
          "\"quantize_bits\": %d, \"keep_order\": %s",
          (unsigned long long)r.total_bytes, (unsigned long long)r.header_bytes,
          (unsigned long long)r.connectivity_bytes, (unsigned long long)r.geometry_bytes,
          (unsigned long long)r.order_bytes, (unsigned long long)r.texcoord_bytes,
          (unsigned long long)r.label_bytes, (unsigned long long)r.tag_bytes,
          (unsigned long long)r.normal_bytes, (unsigned long long)r.exact_bytes,
          (unsigned long long)r.color_bytes, (unsigned long long)r.property_bytes,
          (unsigned long long)r.comment_bytes, (unsigned long long)r.kept_line_bytes,
          (unsigned long long)r.other_bytes, 8.0 * r.total_bytes / v, 8.0 * r.connectivity_bytes / v,
          8.0 * r.geometry_bytes / v, r.version_major, r.version_minor, r.level,
          json_string(r.geometry_tools).c_str(), r.geometry_order, r.quantize_bits,
          r.keep_order ? "true" : "false");
    }
    if (verbose) {
      std::printf(", \"components\": [");
      for (std::size_t c = 0; c < r.comps.size(); ++c) {
        const auto& k = r.comps[c];
        std::printf(
            "%s{\"kind\": \"%s\", \"vertices\": %llu, \"edges\": %llu, \"faces\": %llu, \"euler\": %lld, "
            "\"extraordinary\": %llu, \"schematic\": {\"vertices\": %llu, \"edges\": %llu, \"patches\": "
            "%llu}}",
            c ? ", " : "", k.kind, (unsigned long long)k.vertices, (unsigned long long)k.edges,
            (unsigned long long)k.faces, (long long)k.euler, (unsigned long long)k.extraordinary,
            (unsigned long long)k.sx, (unsigned long long)k.se, (unsigned long long)k.patches);
      }
      std::printf("]");
    }
    std::printf("}%s\n", sep);
  }
  if (!lines) std::printf("]\n");
}

void print_table(const std::vector<Row>& rows, bool verbose) {
  if (std::all_of(rows.begin(), rows.end(), [](const Row& r) { return !r.error.empty(); })) return;
  int width = 5;  // the model column fits the longest name
  for (const Row& r : rows) {
    if (!r.error.empty()) continue;
    const std::size_t n = r.file.size() + (r.partition == "motorcycle" ? 0 : r.partition.size() + 3);
    width = std::max(width, static_cast<int>(n));
  }
  std::printf("%-*s %9s %9s %9s %6s | %7s %7s %7s | %7s %7s\n", width, "model", "V", "E", "F", "xord",
              "sch.V", "sch.E", "patches", "V%", "E%");
  for (const Row& r : rows) {
    if (!r.error.empty()) continue;  // said on stderr
    const std::string model = r.partition == "motorcycle" ? r.file : r.file + " [" + r.partition + "]";
    std::printf("%-*s %9llu %9llu %9llu %6llu | %7llu %7llu %7llu | %6.2f%% %6.2f%%\n", width, model.c_str(),
                (unsigned long long)r.vertices, (unsigned long long)r.edges, (unsigned long long)r.faces,
                (unsigned long long)r.extraordinary, (unsigned long long)r.sx, (unsigned long long)r.se,
                (unsigned long long)r.patches, pct(r.sx, r.vertices), pct(r.se, r.edges));
    if (r.polygon) {
      const PolygonCounts& n = r.polygons;
      std::printf(
          "  polygons: %u quads, %u triangles, %u n-gons; %u cut vertices (%u cut edges, %u extra "
          "copies); the row is the quad submesh's; %llu vertices in all\n",
          n.quads, n.triangles, n.ngons, n.cut_vertices, n.cut_edges, n.extra_copies,
          (unsigned long long)r.mesh_vertices);
    }
    if (r.has_bytes) {
      const double v = per_vertex(r);
      std::printf(
          "  bytes: %llu total = %llu header + %llu connectivity (%.3f bits/vertex) + %llu geometry (%.2f "
          "bits/vertex)",
          (unsigned long long)r.total_bytes, (unsigned long long)r.header_bytes,
          (unsigned long long)r.connectivity_bytes, 8.0 * r.connectivity_bytes / v,
          (unsigned long long)r.geometry_bytes, 8.0 * r.geometry_bytes / v);
      if (r.order_bytes) std::printf(" + %llu order", (unsigned long long)r.order_bytes);
      if (r.texcoord_bytes) std::printf(" + %llu texture coordinates", (unsigned long long)r.texcoord_bytes);
      if (r.label_bytes) std::printf(" + %llu face labels", (unsigned long long)r.label_bytes);
      if (r.tag_bytes) std::printf(" + %llu subdivision tags", (unsigned long long)r.tag_bytes);
      if (r.normal_bytes) std::printf(" + %llu normals", (unsigned long long)r.normal_bytes);
      if (r.exact_bytes) std::printf(" + %llu exact positions", (unsigned long long)r.exact_bytes);
      if (r.color_bytes) std::printf(" + %llu colours", (unsigned long long)r.color_bytes);
      if (r.property_bytes) std::printf(" + %llu properties", (unsigned long long)r.property_bytes);
      if (r.comment_bytes) std::printf(" + %llu comments", (unsigned long long)r.comment_bytes);
      if (r.kept_line_bytes) std::printf(" + %llu kept lines", (unsigned long long)r.kept_line_bytes);
      if (r.other_bytes) std::printf(" + %llu other", (unsigned long long)r.other_bytes);
      if (r.polygon) {
        std::printf(
            "\n  polygons section: %llu connectivity (%.2f bits per non-quad face, in the connectivity "
            "above)",
            (unsigned long long)r.polygon_connectivity_bytes, bits_per_non_quad(r));
        if (r.interior_positions > 0) {
          std::printf("; the positions of its %llu vertices in no quad are in the geometry section",
                      (unsigned long long)r.interior_positions);
        } else if (r.polygon_positions_bytes > 0) {
          std::printf(" + %llu interior positions (in the geometry above)",
                      (unsigned long long)r.polygon_positions_bytes);
        }
      }
      const std::string positions = r.quantize_bits > 0
                                        ? "quantized to " + std::to_string(r.quantize_bits) + " bits"
                                    : r.quantize_bits == 0 ? "lossless"
                                                           : "positions unknown";
      const std::string level = r.level ? "level " + std::to_string(r.level) : "level not said";
      std::printf("\n  format %d.%d, %s, geometry %s order, tools: %s; %s, %s\n", r.version_major,
                  r.version_minor, level.c_str(), r.geometry_order, r.geometry_tools.c_str(),
                  positions.c_str(), r.keep_order ? "original order kept" : "canonical order");
      // What that level searched, in compress --help's words (a file from a newer qsp may name one
      // this build does not know).
      if (r.level >= kMinLevel && r.level <= kMaxLevel)
        std::printf("  level %d: %s\n", r.level, level_description(r.level).c_str());
    }
    if (!verbose) continue;
    for (std::size_t c = 0; c < r.comps.size(); ++c) {
      const auto& k = r.comps[c];
      std::printf("  component %-4zu %-12s %9llu %9llu %9llu %6llu | %7llu %7llu %7llu | chi %lld\n", c,
                  k.kind, (unsigned long long)k.vertices, (unsigned long long)k.edges,
                  (unsigned long long)k.faces, (unsigned long long)k.extraordinary, (unsigned long long)k.sx,
                  (unsigned long long)k.se, (unsigned long long)k.patches, (long long)k.euler);
    }
  }
}

}  // namespace

void register_stats(CLI::App& app, int& rc) {
  auto opt = std::make_shared<StatsOptions>();
  CLI::App* cmd =
      app.add_subcommand("stats", "Print the paper's Table-1 row (mesh vs schematic partition) per file");
  cmd->add_option("files", opt->files, "Mesh files (.obj .off .ply) or .qsp files")->required();
  cmd->add_flag("--json", opt->json,
                "A JSON array: an object per row (\"relative\" in percent), {\"file\", \"error\"} for a file "
                "that could not be read");
  cmd->add_flag("--json-lines", opt->json_lines, "The same objects, one per line, no array");
  add_format_option(cmd, opt->format);
  cmd->add_flag("--verbose", opt->verbose, "Add a per-component breakdown");
  cmd->add_flag("--sizes", opt->sizes, "For meshes: compress in memory and report the .qsp sizes");
  cmd->add_option("--partition", opt->partition,
                  "Partition: motorcycle (default), greedy, merge, auto (the one compress stores, with its "
                  "sizes), or all (a row each)")
      ->check(CLI::IsMember({"motorcycle", "greedy", "merge", "auto", "all"}));
  cmd->callback([opt, cmd, &rc] {
    const MeshFormat format = parse_format_option(opt->format);
    std::vector<Row> rows;
    std::vector<PartitionMode> modes;
    for (PartitionMode m : {PartitionMode::kMotorcycle, PartitionMode::kGreedy, PartitionMode::kMerge})
      if (opt->partition == "all" || opt->partition == partition_mode_name(m)) modes.push_back(m);
    const bool partition_given = cmd->count("--partition") > 0;
    // A row per partition asked for, of a quad mesh or of a polygon mesh's quad submesh (`polygon`: its
    // PolygonCounts); `encode_with(options)`: the file compress writes (--sizes: each partition's
    // sizes; auto: the default's, as stored).
    const auto add_rows = [&](const std::string& f, const LoadedMesh& loaded, const auto& encode_with,
                              const PolygonCounts* polygon, std::uint64_t mesh_vertices) {
      const auto push = [&](Row r) {
        r.polygon = polygon != nullptr;
        if (polygon) r.polygons = *polygon, r.mesh_vertices = mesh_vertices;
        rows.push_back(std::move(r));
      };
      for (PartitionMode m : modes) {
        Row r = mesh_row(f, loaded, m);
        if (opt->sizes) {
          EncodeOptions eo;
          eo.partition = m;
          add_sizes(r, inspect(encode_with(eo)));
        }
        push(std::move(r));
      }
      if (opt->partition == "auto" || opt->partition == "all")
        push(info_row(f, encode_with(EncodeOptions{}), "auto"));
    };
    const auto add_mesh_rows = [&](const std::string& f, const LoadedMesh& loaded) {
      add_rows(
          f, loaded, [&](const EncodeOptions& eo) { return encode(loaded.mesh, eo); }, nullptr, 0);
    };
    // A polygon mesh: the rows of its quad submesh, with its PolygonCounts, sizes from encode_polygons;
    // a polygon .qsp's stored row comes from its bytes.
    const auto add_polygon_rows = [&](const std::string& f, PolygonInput in) {
      const ReadReport report = std::move(in.report);
      const std::string bytes = std::move(in.bytes);
      const PolygonMesh mesh = polygons_of(std::move(in));
      QuadSubmesh s;
      try {
        s = quad_submesh(mesh.face_offsets, mesh.corners, static_cast<std::uint32_t>(mesh.vertex_count()),
                         mesh.positions);
      } catch (const Error& e) {
        rethrow_located(e, f, report);
      }
      if (!bytes.empty()) {
        rows.push_back(info_row(f, bytes, "stored"));
        rows.back().polygons = s.counts;
        rows.back().mesh_vertices = mesh.vertex_count();
        if (!partition_given) return;
      }
      add_rows(
          f, LoadedMesh{std::move(s.mesh), std::move(s.adjacency), {}},
          [&](const EncodeOptions& eo) { return encode_polygons(mesh, eo); }, &s.counts, mesh.vertex_count());
    };
    std::size_t file_start = 0;  // rows of the file being read: dropped if it fails part-way
    const auto one = [&](std::size_t i) {
      file_start = rows.size();
      const std::string& f = opt->files[i];
      PolygonInput in = read_polygon_input(f, format);
      if (!in.qsp && !in.quads) return add_polygon_rows(f, std::move(in));
      if (!in.qsp) {
        Adjacency adjacency;
        try {
          adjacency = build_adjacency(in.mesh);
        } catch (const Error& e) {
          // Quads only, but non-manifold or mis-oriented: cut apart as any polygon mesh is.
          if (!polygon_path_takes(e)) rethrow_located(e, f, in.report);
          return add_polygon_rows(f, std::move(in));
        }
        return add_mesh_rows(f, LoadedMesh{std::move(in.mesh), std::move(adjacency), std::move(in.report)});
      }
      rows.push_back(info_row(f, in.bytes, "stored"));
      if (!partition_given) return;
      // --partition asks for partitions the file does not store: decode it and compute them.
      add_mesh_rows(f, with_adjacency(decode_named(in.bytes, f), {}, f));
    };
    const auto failed = [&](std::size_t i, const std::string& message) {
      rows.resize(file_start);
      Row r;
      r.file = opt->files[i];
      r.error = message;
      rows.push_back(r);
    };
    rc = for_each_file(opt->files, one, failed);
    if (opt->json || opt->json_lines)
      print_json(rows, opt->verbose, opt->json_lines);
    else
      print_table(rows, opt->verbose);
  });
}

}  // namespace qsp::cli
