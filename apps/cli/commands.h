// Subcommands of the `freeform` tool. Each adds itself to the app and runs when selected.
#pragma once

#include "freeform/common/error.h"

#include <CLI/CLI.hpp>

namespace freeform::cli {

// Exit codes (docs/cli.md).
enum ExitCode : int {
  kOk = 0,
  kBadInput = 1,     // input file unreadable, malformed, or refused
  kUsage = 2,        // bad command line
  kWriteFailed = 3,  // output could not be written (nothing partial is left behind)
  kInternal = 4,     // a bug: please report
};

// Thrown when an output cannot be written (exit code kWriteFailed).
struct OutputError : Error {
  using Error::Error;
};

void add_info_command(CLI::App& app);
void add_convert_command(CLI::App& app);
void add_deform_command(CLI::App& app);
void add_render_command(CLI::App& app);  // only with FREEFORM_BUILD_VIEWER

}  // namespace freeform::cli
