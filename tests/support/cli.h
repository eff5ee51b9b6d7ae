// Running the qsp binary from tests: exit code, stdout and stderr (files.h comes with it).
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>

#include "files.h"

namespace qsp::testing {

struct CliResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs `qsp ARGS` through the shell (ARGS must be shell-quoted by the caller).
inline CliResult run_qsp(const std::string& args) {
  static int counter = 0;
  const std::string base =
      ::testing::TempDir() + "qsp_cli_" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
  const std::string cmd =
      std::string("'") + QSP_CLI_PATH + "' " + args + " >'" + base + ".out' 2>'" + base + ".err'";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(base + ".out");
  r.err = slurp(base + ".err");
  std::remove((base + ".out").c_str());
  std::remove((base + ".err").c_str());
  return r;
}

inline std::string quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace qsp::testing
