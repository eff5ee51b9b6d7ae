// qsp command-line entry: parses, runs one subcommand, and holds the one table of exit codes.
#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

#ifdef __GLIBC__
#include <malloc.h>
#include <sys/mman.h>
#endif

#include "commands.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/version.h"
#include "shared.h"

namespace qsp::cli {

// Every exit code qsp returns (README "Exit codes"; docs/matching.md for match). match answers like cmp,
// so that 1 never means broken input there: "not isomorphic" is its 1, and a refused input its 2.
struct ExitRow {
  Outcome outcome;
  int tool;     // compress, decompress, stats, fingerprint, reorder, show, layout
  int compare;  // match
};
constexpr ExitRow kExitCodes[] = {
    {Outcome::kSuccess, 0, 0}, {Outcome::kDiffer, 1, 1}, {Outcome::kRefused, 1, 2},
    {Outcome::kUsage, 2, 2},   {Outcome::kIo, 3, 3},     {Outcome::kInternal, 4, 4},
};

int exit_code(Outcome outcome, Answers answers) {
  for (const ExitRow& row : kExitCodes)
    if (row.outcome == outcome) return answers == Answers::kCompare ? row.compare : row.tool;
  return 4;
}

Outcome outcome_of(ErrorCode code) {
  switch (code) {
    case ErrorCode::kUsage:
      return Outcome::kUsage;
    case ErrorCode::kIo:
      return Outcome::kIo;
    case ErrorCode::kInternal:
      return Outcome::kInternal;
    default:
      return Outcome::kRefused;  // the input: a mesh qsp cannot store, a damaged or newer .qsp, a limit
  }
}

}  // namespace qsp::cli

namespace {

// After a usage error: the subcommand or option the user probably meant, or "" when nothing is near.
std::string suggestion(CLI::App& app, int argc, char** argv) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
  int i = 1;
  while (i < argc && argv[i][0] == '-') ++i;
  if (i == argc) return "";
  CLI::App* sub = nullptr;
  for (CLI::App* s : app.get_subcommands({}))
    if (s->get_name() == argv[i]) sub = s;
  if (!sub) {
    const std::string near = qsp::cli::nearest(argv[i], names);
    return std::string("'") + argv[i] + "' is not a subcommand" +
           (near.empty() ? "" : "; did you mean " + near + "?") + " (qsp --help lists them)";
  }
  std::vector<std::string> options;
  for (const CLI::Option* opt : sub->get_options()) {
    for (const std::string& n : opt->get_lnames()) options.push_back("--" + n);
  }
  for (int k = i + 1; k < argc; ++k) {
    std::string word = argv[k];
    if (word == "--") break;
    if (word.rfind("--", 0) != 0) continue;
    word = word.substr(0, word.find('='));
    if (std::find(options.begin(), options.end(), word) != options.end()) continue;
    const std::string near = qsp::cli::nearest(word, options);
    return word + " is not an option of qsp " + sub->get_name() +
           (near.empty() ? "" : "; did you mean " + near + "?") + " (qsp " + sub->get_name() +
           " --help lists them)";
  }
  return "";
}

#ifdef __GLIBC__
// The heap's first 64 MiB, grown now (virtual memory only: nothing is touched) and kept (the trim
// threshold above), asks for transparent huge pages where the kernel gives them on request (Debian's
// "madvise" setting): one fault and a 2 MiB zeroing in place of 512 faults. Compressing mh_base: page
// faults 2,130 -> 280, wall time 0.90x; mh_female_generic_cc2 0.93x both ways. Where the kernel says
// no, nothing changes. The heap up to the first 2 MiB boundary cannot have a huge page: a block never
// touched (so never backed) fills it, or the first blocks, the input file's among them, came from
// there a page at a time (mh_female_generic's 1.2 MB OBJ: 300 faults of 10 us each on a VM; its
// compress 0.87x the wall time of the static build without the filler, page faults 210-460 -> 110).
void* volatile heap_filler = nullptr;  // volatile: a malloc whose block nothing reads may be elided
void prefer_huge_pages() {
  constexpr std::size_t kReserve = std::size_t{64} << 20, kHuge = std::size_t{2} << 20;
  void* block = std::malloc(kReserve);
  if (block == nullptr) return;
  const auto at = reinterpret_cast<std::uintptr_t>(block);
  std::free(block);
  const std::uintptr_t from = (at + kHuge - 1) & ~(kHuge - 1), to = (at + kReserve) & ~(kHuge - 1);
  if (to <= from || madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE) != 0) return;
  // glibc's header before a block: a block of from - at - kChunkHeader bytes ends where the next
  // block's header goes, so that block's bytes start at `from`.
  constexpr std::size_t kChunkHeader = 2 * sizeof(std::size_t);
  if (from - at > 4 * kChunkHeader) heap_filler = std::malloc(from - at - kChunkHeader);
}
#endif

}  // namespace

int main(int argc, char** argv) {
#ifdef __GLIBC__
  // Large blocks come from the heap and freed memory stays there for the next stage to reuse: a fresh
  // page costs a fault and a zeroing (3.5 us each on the benchmark VM), and glibc's default maps and
  // unmaps every block above 128 KiB (compressing mh_base: 2,900 page faults, 2,200 with this).
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  // One arena: a second thread's blocks come from the same heap, and its huge pages (decompressing
  // mh_base: 770 page faults, 530 with this; 0.97x wall time).
  mallopt(M_ARENA_MAX, 1);
  prefer_huge_pages();
#endif
  CLI::App app{"qsp: quad mesh compression by canonical motorcycle-graph partition"};
  // The file format too: users keeping .qsp archives need to know what this build writes and reads.
  const std::string major = std::to_string(qsp::kFormatMajor) + ".";
  const std::string writes = major + std::to_string(qsp::kFormatMinor);
  app.set_version_flag("--version", std::string("qsp ") + qsp::version() + " (writes .qsp format " + writes +
                                        ", " + major + std::to_string(qsp::kFormatMinorQuads) +
                                        " for manifold quad meshes without a mirror; reads " + major +
                                        "0 to " + writes + ")");
  app.require_subcommand(1);
  // Test seam (tests/test_hostile.cpp, AtomicOutput): stop just before an output file gets its name, so
  // a test knows its kill lands while only the temporary file exists.
  if (const char* stop = std::getenv("QSP_TEST_STOP_BEFORE_RENAME"); stop && std::string(stop) == "1")
    qsp::set_before_rename_hook([] { std::raise(SIGSTOP); });
  int rc = 0;  // set by the subcommand's callback (exit_code())
  // Only the subcommand named first, when one is: building all eight with their options was 0.8 M of
  // the 2.2 M instructions of compressing one quad. --help, --version and a misspelt name get them all.
  struct Subcommand {
    const char* name;
    void (*add)(CLI::App&, int&);
  };
  static constexpr Subcommand kSubcommands[] = {{"compress", qsp::cli::register_compress},
                                                {"decompress", qsp::cli::register_decompress},
                                                {"stats", qsp::cli::register_stats},
                                                {"match", qsp::cli::register_match},
                                                {"fingerprint", qsp::cli::register_fingerprint},
                                                {"reorder", qsp::cli::register_reorder},
                                                {"show", qsp::cli::register_show},
                                                {"layout", qsp::cli::register_layout}};
  const Subcommand* named = nullptr;
  for (const Subcommand& s : kSubcommands)
    if (argc > 1 && std::string_view(argv[1]) == s.name) named = &s;
  for (const Subcommand& s : kSubcommands)
    if (!named || named == &s) s.add(app, rc);
  using qsp::cli::Outcome;
  // match answers like cmp (kExitCodes); every other subcommand as a tool.
  const auto answers = [&] {
    // (Asking CLI11 about a subcommand not added throws.)
    const bool match = named ? std::string_view(named->name) == "match" : app.got_subcommand("match");
    return match ? qsp::cli::Answers::kCompare : qsp::cli::Answers::kTool;
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const std::string hint = e.get_exit_code() == 0 ? "" : suggestion(app, argc, argv);
    if (hint.find("is not a subcommand") != std::string::npos) {
      // CLI11 would say "A subcommand is required", which is not what went wrong.
      std::fprintf(stderr, "qsp: error: %s\n", hint.c_str());
      return qsp::cli::exit_code(Outcome::kUsage);
    }
    if (app.exit(e) == 0) return qsp::cli::exit_code(Outcome::kSuccess);  // --help, --version
    if (!hint.empty()) std::fprintf(stderr, "qsp: %s\n", hint.c_str());
    return qsp::cli::exit_code(Outcome::kUsage);
  } catch (const qsp::Error& e) {
    std::fprintf(stderr, "qsp: error: %s\n", e.what());
    return qsp::cli::exit_code_for(e.code(), answers());
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "qsp: error: out of memory\n");
    return qsp::cli::exit_code(Outcome::kInternal, answers());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "qsp: internal error: %s\n", e.what());
    return qsp::cli::exit_code(Outcome::kInternal, answers());
  }
  return rc;
}
