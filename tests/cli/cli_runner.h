// Runs the `freeform` executable (FREEFORM_CLI_PATH) through the shell for end-to-end tests.
#pragma once

#include "test_support.h"

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <string>

namespace freeform::test {

struct CliRun {
  int exit_code;
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// `freeform ARGS`, capturing stdout, stderr and the exit code.
inline CliRun freeform_cli(const std::string& args) {
  ScratchDir tmp;
  const std::string cmd = std::string(FREEFORM_CLI_PATH) + " " + args + " >" + (tmp / "out").string() + " 2>" +
                          (tmp / "err").string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(tmp / "out"), slurp(tmp / "err")};
}

// Single-quoted for the shell.
inline std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

inline void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

}  // namespace freeform::test
