// tools/qsp/commands.h: one register function per subcommand (one file each), bound to an options struct.
#pragma once

#include <CLI/CLI.hpp>

namespace qsp::cli {

// Each adds its subcommand to `app`; the callback runs the command and returns its exit code
// through `exit_code` (0 ok; errors are thrown as qsp::Error and mapped in main.cpp).
void register_stats(CLI::App& app, int& exit_code);
void register_compress(CLI::App& app, int& exit_code);
void register_decompress(CLI::App& app, int& exit_code);
// match exits 0 isomorphic / 1 not / 2 invalid input (cmp-style); it maps qsp::Error itself.
void register_match(CLI::App& app, int& exit_code);
void register_fingerprint(CLI::App& app, int& exit_code);
void register_reorder(CLI::App& app, int& exit_code);
void register_show(CLI::App& app, int& exit_code);
void register_layout(CLI::App& app, int& exit_code);

}  // namespace qsp::cli
