// tools/qsp/shared.h: what the subcommands share, in one place: exit codes (the table is in main.cpp),
// which inputs and outputs a call names and the one check that no output is an input or another
// output, writing an output (links, -f), reading a mesh or .qsp from a file or standard input (format
// option or detected, errors located as file:line), refusing data .qsp does not keep, --centering, and
// going on after a bad file.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/match.h"
#include "qsp/mesh.h"

namespace qsp::cli {

// ---- Exit codes (README "Exit codes", docs/matching.md): the table is kExitCodes in main.cpp ----

// How a call ended.
enum class Outcome {
  kSuccess,
  kDiffer,    // match: the meshes are not isomorphic (cmp's 1)
  kRefused,   // bad or refused input: a mesh qsp cannot store, a damaged .qsp, an output that exists
  kUsage,     // unknown option, missing argument, a value outside its range
  kIo,        // a file cannot be read or written
  kInternal,  // a bug in qsp (never a wrong result instead), or out of memory
};
// Who answers: every subcommand but match, or match, which answers like cmp (0 same, 1 differ, 2 trouble).
enum class Answers { kTool, kCompare };

// The exit code of `outcome` for subcommands that answer as `answers` do; one table, in main.cpp.
int exit_code(Outcome outcome, Answers answers = Answers::kTool);
// The outcome a qsp::Error stands for.
Outcome outcome_of(ErrorCode code);
// exit_code(outcome_of(code), answers): what main and the batch loop return for an error.
inline int exit_code_for(ErrorCode code, Answers answers = Answers::kTool) {
  return exit_code(outcome_of(code), answers);
}

// ---- Outputs ----

// An output a call will write, and what named it in the command line ("-o", "--faces", "OUT", or the
// input it is derived from), for the messages.
struct Output {
  std::string path;
  std::string named_by;
};

// The one check of every subcommand: refuses (Error kIo, nothing written) when an output is one of
// the inputs or another output, by name, by path (`sub/../x`, absolute or relative) or by link (a
// symbolic link to it, a hard link: same device and inode). "-" (standard output) may be named once.
// Call it before writing anything.
void check_outputs(const std::vector<std::string>& inputs, const std::vector<Output>& outputs);

// How an output is written. `other_ways`: what else the user can do instead of -f, named in the
// refusal ("-o NAME, --output-dir DIR or -c").
struct WriteOptions {
  bool force = false;
  bool quiet = false;
  std::string other_ways = "-o NAME";
  bool sync = false;  // --sync: flushed to disk before it gets its name (write_file_atomic)
};

// --sync, for every command that writes files: one flag, one help text.
void add_sync_flag(CLI::App* command, bool& sync);

// Writes `bytes` to `path` atomically (qsp::write_file_atomic). An existing file is refused (kIo)
// unless `force`, the message naming -f and `other_ways`. A symbolic link is written through (its
// target is replaced, the link stays) and a note on stderr says so unless quiet. "-" is standard
// output.
void write_output(const std::string& path, std::string_view bytes, const WriteOptions& o);

// For a call that writes several outputs (match's maps, layout's files): refuses (kIo, as write_output
// would) when one of them exists and `o.force` is not set, before any is written, so a refusal leaves
// none half done. "-" is never refused.
void refuse_existing(const std::vector<Output>& outputs, const WriteOptions& o);

// ---- Reading meshes ----

// The --format option's value as a mesh format; kUnknown for "" (detect). Throws CLI::ValidationError
// for anything but obj, off or ply.
MeshFormat parse_format_option(const std::string& value);

// Adds `--format obj|off|ply` (for standard input, or a file whose name says nothing) to `cmd`.
void add_format_option(CLI::App* cmd, std::string& value);

// Reads a mesh from `path` ("-" = standard input): in `format` (--format) where the name says no format
// (standard input, an unknown extension; a file named x.obj is read by its name whatever --format says,
// so one option serves A and B of match), else by extension, else by the bytes' first line ("OFF",
// COFF, NOFF, ..., or "ply"; OBJ on standard input). A folder or a .qsp is refused with a message saying
// what it is (a folder: how to name the files in it). Throws qsp::Error as the readers do. Safe on
// untrusted input.
QuadMesh read_input_mesh(const std::string& path, MeshFormat format, ReadReport* report);

// A file named on the command line, read as what it is: a .qsp (by its name, or by its magic on standard
// input or under a name that says nothing) kept as bytes, or a mesh with the reader's report (face
// lines, data dropped).
struct Input {
  bool qsp = false;
  std::string bytes;  // the .qsp's bytes, unchecked
  QuadMesh mesh;      // a mesh file's mesh
  ReadReport report;
};

// Reads `path` ("-" = standard input) as read_input_mesh does, except that .qsp bytes are returned as
// they are. `format` (--format) as there. Throws qsp::Error as the readers do. Safe on untrusted input.
Input read_input(const std::string& path, MeshFormat format = MeshFormat::kUnknown);

// decode(bytes, limits) (codec.h) with an error's message starting "path: ".
QuadMesh decode_named(std::string_view bytes, const std::string& path, const DecodeLimits& limits = {});
// file_comments(bytes) (codec.h) with an error's message starting "path: ".
std::vector<std::string> comments_named(std::string_view bytes, const std::string& path);

// read_input, with a .qsp decoded in full (vertices numbered as `qsp decompress` writes them; a decode
// error names the file). `report` gets a mesh file's face lines (none for a .qsp).
QuadMesh read_mesh_or_qsp(const std::string& path, ReadReport& report,
                          MeshFormat format = MeshFormat::kUnknown);

// A mesh with its adjacency, and the reader's report.
struct LoadedMesh {
  QuadMesh mesh;
  Adjacency adjacency;
  ReadReport report;
};

// `mesh` with its adjacency built; an Error found at a face (non-manifold edge, orientation, ...) is
// rethrown as "path:LINE: ..." using the line `report` has for the face. Throws qsp::Error.
LoadedMesh with_adjacency(QuadMesh mesh, ReadReport report, const std::string& path);

// Rethrows `e` with "path:LINE: " in front when it names a face the report has a line for.
[[noreturn]] void rethrow_located(const Error& e, const std::string& path, const ReadReport& report);

// prepare_match(mesh) (match.h) with topology errors located as "path:LINE: ..." (rethrow_located).
MatchInput prepare_located(QuadMesh mesh, const std::string& path, const ReadReport& report);

// ---- Polygon meshes (compress, match, fingerprint, stats, reorder: faces of any degree, non-manifold
// pieces) ----

// A file read for the subcommands that take any polygon mesh: a .qsp of quads kept as bytes (`qsp`), or
// decoded as a quad mesh; a quad mesh file as read_input reads it (`quads`); else a polygon mesh
// (`polygons`): a mesh file with a face that is not a quad, or a .qsp holding a polygon mesh (3.1).
struct PolygonInput {
  bool qsp = false;
  std::string bytes;      // the .qsp's bytes, their container checked (kBytes: a polygon .qsp's too)
  bool from_qsp = false;  // the mesh below was decoded from a .qsp
  bool quads = false;
  QuadMesh mesh;  // quads
  PolygonMesh
      polygons;  // neither: float32 positions, faces and corners as read (texture coordinates if kept)
  std::uint64_t rounded_texcoords =
      0;  // kept texture coordinate, normal and colour values float32 does not hold
  std::string first_rounded_texcoord;       // which is the first of them and its value, for messages
  unsigned rounded_categories = 0;          // the categories (kCategoryUv, ...) of those values
  std::uint64_t values_beyond_float64 = 0;  // of those, values of more digits than float64 holds
  std::string first_value_beyond_float64;   // which is the first of them and its value, for messages
  std::uint64_t beyond_float64 = 0;         // coordinates of more digits than float64 holds (decimal text)
  std::string first_beyond_float64;         // which is the first of them and its value, for messages
  // The reader's report. A polygon mesh file's says what the quad reader's would (its data besides
  // positions and faces by kind, face lines, leading comments, coordinates float32 does not hold); a
  // decoded .qsp's has the lines of its comments section.
  ReadReport report;
};

// What read_polygon_input does with a .qsp of quads: keeps its bytes (fingerprint and stats read it
// without decoding positions), decodes it (match, reorder), or refuses it, and a polygon .qsp too
// (compress: kUnsupported, it is no mesh file).
enum class QspInput { kBytes, kDecoded, kRefused };

// What read_polygon_input does with coordinates float32 does not hold: reads them exactly (the exact
// reader, a polygon mesh), or rounds them in a quad mesh (match, fingerprint: they read the topology
// and, among a symmetric mesh's isomorphisms, the nearest, which only the quad way searches in full).
enum class Coordinates { kExact, kRounded };

// Reads `path` ("-" = standard input) once, as read_input does; where the quad reader refuses a face that
// is not a quad (kNotQuad), the same bytes again with the exact reader (read_obj_mesh, read_off_mesh,
// read_ply_mesh; their errors), a coordinate rounding to infinity, or a nonzero one to zero, in float32
// refused (kBadNumber) as the quad reader refuses it. An OBJ whose faces name texture coordinates or
// normals that `keep` keeps goes to the exact reader first (the quad reader only where that one refuses
// the file or its coordinates need the quad reader's words): the same mesh and report either way. A .qsp
// holding a polygon mesh (3.1) is decoded into `polygons`, its texture coordinates counted in the report; a
// quad .qsp as `qsp` says. `format`
// (--format) as for read_input. `keep`: the categories of a mesh file's data read (by the exact reader)
// into `polygons` (of kPolygonMeshCategories: texture coordinates, face labels). Throws qsp::Error as the
// readers and the decoder do, naming `path`. Safe on untrusted input.
PolygonInput read_polygon_input(const std::string& path, MeshFormat format = MeshFormat::kUnknown,
                                QspInput qsp = QspInput::kBytes, unsigned keep = 0,
                                Coordinates coordinates = Coordinates::kExact);

// The mesh of a read mesh file or decoded .qsp as a polygon mesh (its quads, or its polygons): moved
// out of `in`, whose report and counts stay; or copied.
PolygonMesh polygons_of(PolygonInput&& in);
PolygonMesh polygons_of(const PolygonInput& in);

// Whether an error preparing a quad mesh (build_adjacency's) means the mesh is a polygon mesh's
// business: an edge with three or more faces, a vertex with several fans, neighbours of opposite
// orientation (kNonManifold, kOrientation), which the polygon path cuts apart.
bool polygon_path_takes(const Error& e);

// Two polygon meshes of quads alone (read with their data by the exact reader, or decoded from a polygon
// .qsp): matched as quad meshes of their float32 positions, which searches a symmetric mesh's isomorphisms
// for the nearest (match_polygons takes one of them). Empty where either has another face or the quad way
// refuses it (non-manifold, mis-oriented, ...): the polygon way then says what it refuses, where.
std::optional<MatchResult> match_as_quads(const PolygonMesh& a, const PolygonMesh& b,
                                          const MatchOptions& options);

// prepare_polygon_match (match.h) with an error at a face located as "path:LINE: ..." (rethrow_located).
PolygonMatchInput prepare_polygon_located(PolygonMesh mesh, const std::string& path,
                                          const ReadReport& report);

// --drop LIST and --positions-only (compress, reorder, decompress): the kinds of data (qsp/polymesh.h's
// categories) a call drops instead of refusing a file, or an output format, that cannot hold them.
struct DropOptions {
  std::string list;  // --drop, as given ("uv,normal")
  bool positions_only = false;
  unsigned categories() const;  // checked by add_drop_options
};

// Adds --drop LIST (checked: an unknown item is a usage error naming the valid ones) and
// --positions-only to `cmd`; `whose` ("", "IN's "), `kept` (the categories the subcommand keeps
// unless dropped) and `refused` (what is refused unless dropped; empty: a file with any of the kinds not
// kept) for the help.
void add_drop_options(CLI::App* cmd, DropOptions& drop, const std::string& whose, unsigned kept = 0,
                      const std::string& refused = "");

// Data a mesh file had beside positions and faces (texture coordinates, normals, groups, ...), which
// `what` (".qsp", "reorder") cannot keep: refused (kUnsupported, naming each kind not dropped with its
// counts, and the --drop that drops everything the file has) unless `drop` drops every kind the file
// has; then returns the note naming what was dropped ("" if nothing was, or `quiet`), for the caller to
// print once its output is written. The leading comment block is kept by both (kKeptCategories):
// never refused, dropped only when `drop` names it.
inline constexpr unsigned kKeptCategories = kCategoryComment;
// The report without the extra data a PolygonMesh keeps when `keep` has kCategoryExtra (lines kept as text,
// vertex weights, PLY properties and obj_info lines): what is left for refuse_extra_data.
ReadReport refusable_extra(const ReadReport& report, unsigned keep);
// `kept`: the categories `what` keeps (compress: uv), refused only when `drop` names them.
std::string refuse_extra_data(const std::string& path, const ReadReport& report, const std::string& what,
                              const DropOptions& drop, bool quiet, unsigned kept = 0);

// The leading comment lines to write with the mesh: the report's, unless `drop` drops comments.
std::vector<std::string> kept_comments(const ReadReport& report, const DropOptions& drop);

// Coordinates the reader rounded to float32 (ReadReport::rounded_coordinates), which `what` would
// write rounded: refused (kUnsupported, naming the first and --float32, plus `other_way` when not
// empty) unless `float32`, then a note on stderr unless `quiet`. A lossless file must not change a
// mesh without a word.
void refuse_rounding(const std::string& path, const ReadReport& report, const std::string& what, bool float32,
                     bool quiet, const std::string& other_way = "");

// Removes from `mesh` (a decoded .qsp's), and from its leading comment block `comments` when given, the
// kinds `drop` names and returns the note saying which it had ("" if none).
std::string drop_polygon_data(PolygonMesh& mesh, const std::string& path, const DropOptions& drop,
                              std::vector<std::string>* comments = nullptr);

// How compress and reorder keep IN's values beside positions and faces (check_kept_values).
struct KeptRules {
  std::string what;        // ".qsp", "reorder": what keeps them, for messages
  std::string lines_note;  // where lines kept as text go ("decompress writes them back before the vertices");
                           // empty: no note (the output then refuses them)
  bool float32 = false;    // --float32: round what float32 does not hold instead of refusing
  bool quantized = false;  // --quantize: positions are rounded anyway
  bool quiet = false;
  unsigned quantized_values = 0;  // kCategoryUv, kCategoryNormal, kCategoryColor quantized (rounded anyway)
};
// Checks `mesh`, read from `path` by read_polygon_input (`input`: its report and counts), as `rules`
// keep it: text with no vertex but lines kept as text is not a mesh (kParse); a kept line that would read
// as a statement is refused (--drop extra), else noted on stderr; coordinates of more digits than float64
// holds are refused unless rounded (--float32 or quantized: then `mesh.positions64` is cleared, the
// rounding noted); texture coordinates, normals and colours float32 does not hold are kept as float64
// (format 3.13's exact values section) unless rounded (--float32, noted, or their quantization: then the
// mesh's texcoords64 and the like are cleared), and refused where float64 does not hold them either,
// naming the first and the --drop that drops them. A lossless file must not change a mesh without a word.
void check_kept_values(const std::string& path, const PolygonInput& input, PolygonMesh& mesh,
                       const KeptRules& rules);

// ---- Options shared by subcommands ----

// Adds --centering component|mesh|none (MatchOptions::centering) to `cmd`, bound to `value`.
void add_centering_option(CLI::App* cmd, Centering& value);

// ---- Batches and messages ----

// Runs `one` for each file in order; an Error (or CLI::ValidationError) for one file is printed as
// "qsp: error: ..." and the loop goes on. `on_error(i, message)` lets --json record it. Returns 0 if all
// succeeded, else the exit code of the first failure (exit_code_for; 2 for a usage error).
int for_each_file(const std::vector<std::string>& files, const std::function<void(std::size_t)>& one,
                  const std::function<void(std::size_t, const std::string&)>& on_error = {});

// A match reason ("... A has 1, B has 0") with the files' names for A and B.
std::string name_meshes(std::string reason, const std::string& a, const std::string& b);

// "; but B is A with every face reversed ...: pass --allow-mirror ...", for a MatchResult whose
// mirror_would_match is set, with the files' names for A and B.
std::string mirror_hint(const std::string& a, const std::string& b);

// The candidate nearest `word` by edit distance, or "" when none is close enough to suggest.
std::string nearest(const std::string& word, const std::vector<std::string>& candidates);

// ---- One output per input (compress, decompress) ----

// The files of a subcommand that writes one output per input (compress, decompress), gzip's way:
// `IN... `, each written beside its input or into --output-dir; `IN OUT` or `IN -o OUT` for a single
// input (OUT "-" or -c: standard output).
struct FileArgs {
  std::vector<std::string> positional;  // IN... [OUT]
  std::string output;                   // -o
  std::string output_dir;               // --output-dir
  bool to_stdout = false;               // -c
};

// Adds IN... [OUT], -o, --output-dir and -c to `cmd`. `what_in`/`what_out` describe them in --help.
void add_file_args(CLI::App* cmd, FileArgs& args, const std::string& what_in, const std::string& what_out);

// One input and the output it goes to.
struct Job {
  std::string input, output;
  bool derived = false;  // the output name was made from the input's (not given)
};

// How a subcommand names outputs: whether a name is one of its outputs (a positional OUT is taken as
// one only when it is), the output beside an input ("" when none can be made: that input fails with
// `no_default`), and the rule for the messages ("must end in .qsp").
struct OutputNaming {
  std::function<bool(const std::string&)> is_output_name;
  std::function<std::string(const std::string&)> beside;
  std::string rule;
  std::string verb;        // "compress"
  std::string stdin_name;  // standard input's output in --output-dir ("stdin.qsp")
  std::string no_default;  // why an input has no output beside it ("does not end in .qsp")
};

// The jobs of a call, checked: usage errors (an OUT after several inputs, -o or -c with several, an
// OUT that does not exist and is no output name) throw CLI::ValidationError; outputs that collide
// with inputs or each other throw as check_outputs does. --output-dir is created if missing.
std::vector<Job> plan_jobs(const FileArgs& args, const OutputNaming& naming);

// plan_jobs, then `one` for each job as for_each_file runs it (going on after a failure); returns
// for_each_file's exit code.
int run_jobs(const FileArgs& args, const OutputNaming& naming, const std::function<void(const Job&)>& one);

// What the user can do instead of -f for a job's output, for write_output's refusal.
std::string other_ways(const Job& job);

// Output verbosity shared by subcommands: -v/--verbose (a line per file on stderr) and -q/--quiet.
struct Verbosity {
  bool verbose = false;
  bool quiet = false;
};
void add_verbosity_flags(CLI::App* cmd, Verbosity& v);

}  // namespace qsp::cli
