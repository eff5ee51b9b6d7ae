// `qsp fingerprint FILE...`: one line per file, "HHHHHHHHHHHHHHHH  FILE", the 64-bit hash of the
// canonical connectivity (equal exactly when the meshes are isomorphic with orientation, up to
// hash collisions ~2^-64). Polygon meshes (any face degree, non-manifold pieces) hash their quad
// submesh's codes, region codes and glue (polygon_fingerprint). `--group` lists files with equal fingerprints
// together. A .qsp gives the same fingerprint as the mesh it was compressed from.
#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "commands.h"
#include "qsp/error.h"
#include "qsp/fingerprint.h"
#include "qsp/io.h"
#include "qsp/match.h"
#include "shared.h"

namespace qsp::cli {
namespace {

struct FingerprintOptions {
  std::vector<std::string> files;
  bool group = false;
  std::string format;  // --format for standard input
};

// A .qsp without its positions (qsp/fingerprint.h); a damaged file names itself.
std::uint64_t qsp_fingerprint(const std::string& path, const std::string& bytes) {
  try {
    return file_fingerprint(bytes);
  } catch (const Error& e) {
    throw Error(e.code(), path + ": " + e.what());
  }
}

// A polygon mesh's (match.h, fingerprint.h); a warning where a symmetric piece without quads may make
// it depend on the numbering.
std::uint64_t polygon_fingerprint_of(const std::string& path, PolygonInput in) {
  const ReadReport report = std::move(in.report);
  const PolygonMatchInput prepared = prepare_polygon_located(polygons_of(std::move(in)), path, report);
  if (prepared.capped)
    std::fprintf(
        stderr,
        "qsp: warning: %s: a piece of non-quad faces with no quad is too symmetric for its canonical "
        "code to be certain: a renumbered copy may get another fingerprint\n",
        path.c_str());
  return polygon_fingerprint(prepared);
}

std::uint64_t fingerprint_of(const std::string& path, MeshFormat format) {
  PolygonInput in = read_polygon_input(path, format);
  if (in.qsp) return qsp_fingerprint(path, in.bytes);
  if (!in.quads) return polygon_fingerprint_of(path, std::move(in));
  try {
    return mesh_fingerprint(in.mesh);
  } catch (const Error& e) {
    // Quads only, but non-manifold or mis-oriented: cut apart as any polygon mesh is.
    if (!polygon_path_takes(e)) rethrow_located(e, path, in.report);
  }
  return polygon_fingerprint_of(path, std::move(in));
}

// Goes on after a file that cannot be read (its error on stderr); returns the first failure's exit code.
int run(const FingerprintOptions& o) {
  const MeshFormat format = parse_format_option(o.format);
  std::vector<std::uint64_t> fp(o.files.size());
  std::vector<bool> ok(o.files.size(), false);
  const int rc = for_each_file(o.files, [&](std::size_t i) {
    fp[i] = fingerprint_of(o.files[i], format);
    ok[i] = true;
    // Without --group, print as we go: one slow file does not hold back the others' lines.
    if (!o.group) std::printf("%016" PRIx64 "  %s\n", fp[i], o.files[i].c_str());
  });
  if (!o.group) return rc;
  // Groups in order of first appearance, files in command-line order, a blank line between groups.
  std::unordered_map<std::uint64_t, std::size_t> group_of;
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < fp.size(); ++i) {
    if (!ok[i]) continue;
    const auto [it, fresh] = group_of.try_emplace(fp[i], groups.size());
    if (fresh) groups.emplace_back();
    groups[it->second].push_back(i);
  }
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (g) std::printf("\n");
    for (std::size_t i : groups[g]) std::printf("%016" PRIx64 "  %s\n", fp[i], o.files[i].c_str());
  }
  return rc;
}

}  // namespace

void register_fingerprint(CLI::App& app, int& rc) {
  auto opt = std::make_shared<FingerprintOptions>();
  CLI::App* cmd =
      app.add_subcommand("fingerprint", "Print a topology fingerprint per file (equal = isomorphic meshes)");
  cmd->add_option("files", opt->files,
                  "Mesh files (.obj .off .ply), or .qsp (read without decoding positions)")
      ->required();
  cmd->add_flag("--group", opt->group,
                "List files with equal fingerprints together, groups separated by a blank line");
  add_format_option(cmd, opt->format);
  cmd->callback([opt, &rc] { rc = run(*opt); });
}

}  // namespace qsp::cli
