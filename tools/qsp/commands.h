// tools/qsp/commands.h: one register function per subcommand (one file each), bound to an options struct.
#pragma once

#include <CLI/CLI.hpp>

namespace qsp::cli {

// Each adds its subcommand to `app`; the callback runs the command and sets `rc` to its exit code
// (exit_code(), shared.h; errors are thrown as qsp::Error and mapped in main.cpp).
void register_stats(CLI::App& app, int& rc);
void register_compress(CLI::App& app, int& rc);
void register_decompress(CLI::App& app, int& rc);
// match answers like cmp: 0 isomorphic, 1 not, 2 invalid input (Answers::kCompare in main.cpp's table).
void register_match(CLI::App& app, int& rc);
void register_fingerprint(CLI::App& app, int& rc);
void register_reorder(CLI::App& app, int& rc);
void register_show(CLI::App& app, int& rc);
void register_layout(CLI::App& app, int& rc);

}  // namespace qsp::cli
