// qsp command-line entry: parses, runs one subcommand, maps qsp::Error to an exit code in one place.
#include <cstdio>
#include <exception>
#include <string>

#include "commands.h"
#include "qsp/codec.h"
#include "qsp/error.h"

namespace {

// Exit codes (documented in README.md): 0 ok, 1 bad input or refused, 2 usage, 3 I/O, 4 internal.
int exit_code_for(qsp::ErrorCode code) {
  switch (code) {
    case qsp::ErrorCode::kIo:
      return 3;
    case qsp::ErrorCode::kInternal:
      return 4;
    default:
      return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"qsp: quad mesh compression by canonical motorcycle-graph partition"};
  // The file format too: users keeping .qsp archives need to know what this build writes and reads.
  const std::string writes = std::to_string(qsp::kFormatMajor) + "." + std::to_string(qsp::kFormatMinor);
  app.set_version_flag("--version", std::string("qsp ") + QSP_VERSION + " (writes .qsp format " + writes +
                                        ", reads " + std::to_string(qsp::kOldestMajor) + ".0 to " + writes +
                                        ")");
  app.require_subcommand(1);
  int exit_code = 0;
  qsp::cli::register_compress(app, exit_code);
  qsp::cli::register_decompress(app, exit_code);
  qsp::cli::register_stats(app, exit_code);
  qsp::cli::register_match(app, exit_code);
  qsp::cli::register_fingerprint(app, exit_code);
  qsp::cli::register_reorder(app, exit_code);
  qsp::cli::register_show(app, exit_code);
  qsp::cli::register_layout(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  } catch (const qsp::Error& e) {
    std::fprintf(stderr, "qsp: error: %s\n", e.what());
    return exit_code_for(e.code());
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "qsp: error: out of memory\n");
    return 4;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "qsp: internal error: %s\n", e.what());
    return 4;
  }
  return exit_code;
}
