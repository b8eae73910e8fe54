// freeform: command-line front end. Errors go to stderr as "freeform: error: ..." with the
// exit codes of commands.h; nothing is written when a command fails.
#include "commands.h"

#include "freeform/common/error.h"
#include "freeform/common/huge_pages.h"
#include "freeform/common/memory_limit.h"

#include <fmt/core.h>

#include <cstdio>
#include <cstdlib>
#include <exception>

namespace {

// Exits at once: a normal exit runs OpenBLAS's shutdown, which waits forever for a worker
// thread stuck retrying an allocation the memory limit refused. Nothing is left to write (a
// failed command writes nothing; temporaries are removed where the failure happened).
[[noreturn]] void out_of_memory(const char* message) {
  std::fprintf(stderr, "freeform: error: %s\n", message);
  std::fflush(nullptr);
  std::_Exit(freeform::cli::kBadInput);
}

}  // namespace

int main(int argc, char** argv) {
  freeform::restart_with_huge_page_malloc(argv);
  CLI::App app{"Freeform: real-time freeform modeling of triangle meshes (Botsch & Kobbelt 2004)", "freeform"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "freeform 0.1.0");
  freeform::cli::add_info_command(app);
  freeform::cli::add_convert_command(app);
  freeform::cli::add_deform_command(app);
#ifdef FREEFORM_HAVE_RENDER
  freeform::cli::add_render_command(app);
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? freeform::cli::kOk : freeform::cli::kUsage;
  } catch (const freeform::cli::OutputError& e) {
    fmt::print(stderr, "freeform: error: {}\n", e.what());
    return freeform::cli::kWriteFailed;
  } catch (const freeform::InternalError& e) {
    fmt::print(stderr, "freeform: {}\n(this is a bug in freeform; please report it)\n", e.what());
    return freeform::cli::kInternal;
  } catch (const freeform::OutOfMemory& e) {
    out_of_memory(e.what());
  } catch (const freeform::Error& e) {
    fmt::print(stderr, "freeform: error: {}\n", e.what());
    return freeform::cli::kBadInput;
  } catch (const std::bad_alloc&) {
    out_of_memory(freeform::out_of_memory_message().c_str());
  }
  return freeform::cli::kOk;
}
