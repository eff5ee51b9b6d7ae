// `qsp fingerprint FILE...`: one line per file, "HHHHHHHHHHHHHHHH  FILE", the 64-bit hash of the
// canonical connectivity (equal exactly when the meshes are isomorphic with orientation, up to
// hash collisions ~2^-64). `--group` lists files with equal fingerprints together. A .qsp gives the
// same fingerprint as the mesh it was compressed from.
#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <string>
#include <unordered_map>
#include <vector>

#include "commands.h"
#include "files.h"
#include "load.h"
#include "qsp/canonical.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/match.h"
#include "qsp/partition.h"

namespace qsp::cli {
namespace {

struct FingerprintOptions {
  std::vector<std::string> files;
  bool group = false;
  std::string format;  // --format for standard input
};

// prepare_match: the canonical form, computed on a locality-friendly numbering if the file's is scrambled.
std::uint64_t mesh_fingerprint(QuadMesh mesh) {
  return topology_fingerprint(prepare_match(std::move(mesh)).canonical);
}

// A .qsp without its geometry: file_topology() checks the whole file (checksum, counts, topology) and
// returns its codes, rebuilt here into the mesh's connectivity (canonical numbering, positions left at
// zero). The codes cannot be hashed as stored: a file may hold a greedy or merged partition (compress
// chooses the smallest), and the fingerprint is defined on the motorcycle partition.
std::uint64_t qsp_fingerprint(const std::string& path, const std::string& bytes) {
  try {
    const FileTopology topology = file_topology(bytes);
    QuadMesh mesh;
    std::uint32_t base = 0;
    for (const TopologyCode& code : topology.codes) {
      const GridLayout g = grid_layout(partition_from_code(code));
      for (std::uint32_t v : g.quads) mesh.quads.push_back(base + v);
      base += g.vertex_count;
    }
    mesh.positions.assign(3 * (std::size_t(base) + topology.unreferenced), 0.0f);
    return mesh_fingerprint(std::move(mesh));
  } catch (const Error& e) {
    throw Error(e.code(), path + ": " + e.what());
  }
}

std::uint64_t file_fingerprint(const std::string& path, MeshFormat format) {
  std::string bytes;
  ReadReport report;
  QuadMesh mesh;
  if (read_stdin_if_unknown(path, format, bytes)) {
    if (detect_format(bytes) == MeshFormat::kQsp) return qsp_fingerprint(path, bytes);
    mesh = read_mesh_bytes(bytes, path, &report);
  } else if (format_from_path(path) == MeshFormat::kQsp) {
    refuse_folder(path);
    return qsp_fingerprint(path, read_file_bytes(path));
  } else {
    mesh = read_input_mesh(path, format, &report);
  }
  try {
    return mesh_fingerprint(std::move(mesh));
  } catch (const Error& e) {
    rethrow_located(e, path, report);
  }
}

// Goes on after a file that cannot be read (its error on stderr); returns the first failure's exit code.
int run(const FingerprintOptions& o) {
  const MeshFormat format = parse_format_option(o.format);
  std::vector<std::uint64_t> fp(o.files.size());
  std::vector<bool> ok(o.files.size(), false);
  const int rc = for_each_file(o.files, [&](std::size_t i) {
    fp[i] = file_fingerprint(o.files[i], format);
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

void register_fingerprint(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<FingerprintOptions>();
  CLI::App* cmd =
      app.add_subcommand("fingerprint", "Print a topology fingerprint per file (equal = isomorphic meshes)");
  cmd->add_option("files", opt->files,
                  "Mesh files (.obj .off .ply), or .qsp (read without decoding positions)")
      ->required();
  cmd->add_flag("--group", opt->group,
                "List files with equal fingerprints together, groups separated by a blank line");
  add_format_option(cmd, opt->format);
  cmd->callback([opt, &exit_code] { exit_code = run(*opt); });
}

}  // namespace qsp::cli
