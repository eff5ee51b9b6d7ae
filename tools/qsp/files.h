// tools/qsp/files.h: what every subcommand shares about files: which inputs and outputs a call names,
// the one check that no output is an input or another output, writing an output (links, -f), reading
// a mesh from a file or standard input (format option or detected), and going on after a bad file.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/error.h"
#include "qsp/io.h"

namespace qsp::cli {

// The exit code of an error (README "Exit codes"): 1 bad or refused input, 3 I/O, 4 internal. The one
// mapping main.cpp and the batch loop use.
int exit_code_for(ErrorCode code);

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
};

// Writes `bytes` to `path` atomically (qsp::write_file_atomic). An existing file is refused (kIo)
// unless `force`, the message naming -f and `other_ways`. A symbolic link is written through (its
// target is replaced, the link stays) and a note on stderr says so unless quiet. "-" is standard
// output.
void write_output(const std::string& path, std::string_view bytes, const WriteOptions& o);

// Refuses (kIo) a path that is a folder, saying so and how to name the files in it.
void refuse_folder(const std::string& path);

// The --format option's value as a mesh format; kUnknown for "" (detect). Throws CLI::ValidationError
// for anything but obj, off or ply.
MeshFormat parse_format_option(const std::string& value);

// `format` where it applies: to standard input and to a name whose extension says no format; a
// file named x.obj is read by its name whatever --format says (one option serves A and B of match).
MeshFormat format_for(const std::string& path, MeshFormat format);

// Adds `--format obj|off|ply` (for standard input, or a file whose name says nothing) to `cmd`.
void add_format_option(CLI::App* cmd, std::string& value);

// The format of mesh bytes from their first line: "OFF" (also COFF, NOFF, ...) or "ply" magic, else
// OBJ; kQsp for the .qsp magic.
MeshFormat detect_format(std::string_view bytes);

// Reads a mesh from `path` ("-" = standard input): in format_for(path, format) if any, else by extension,
// else (on standard input or an unknown extension) by the bytes' magic. A folder or a .qsp is refused with a
// message saying what it is. Throws qsp::Error as the readers do. Safe on untrusted input.
QuadMesh read_input_mesh(const std::string& path, MeshFormat format, ReadReport* report);

// The detecting half of read_input_mesh, on bytes already read from `path`.
QuadMesh read_mesh_bytes(std::string_view bytes, const std::string& path, ReadReport* report);

// Runs `one` for each file in order; an Error (or CLI::ValidationError) for one file is printed as
// "qsp: error: ..." and the loop goes on. `on_error(i, message)` lets --json record it. Returns 0 if all
// succeeded, else the exit code of the first failure (exit_code_for; 2 for a usage error).
int for_each_file(const std::vector<std::string>& files, const std::function<void(std::size_t)>& one,
                  const std::function<void(std::size_t, const std::string&)>& on_error = {});

// A match reason ("... A has 1, B has 0") with the files' names for A and B.
std::string name_meshes(std::string reason, const std::string& a, const std::string& b);

// The candidate nearest `word` by edit distance, or "" when none is close enough to suggest.
std::string nearest(const std::string& word, const std::vector<std::string>& candidates);

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
