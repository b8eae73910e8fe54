#include "freeform/common/error.h"

namespace freeform {
namespace {
std::string format_io(const std::string& file, std::size_t line, const std::string& message) {
  std::string out = file;
  if (line > 0) out += ":" + std::to_string(line);
  return out + ": " + message;
}
}  // namespace

IoError::IoError(std::string file, std::size_t line, const std::string& message)
    : Error(format_io(file, line, message)), file_(std::move(file)), line_(line), message_(message) {}

void throw_internal(const char* condition, const char* file, int line, const std::string& message) {
  throw InternalError(std::string("internal error (") + condition + ") at " + file + ":" + std::to_string(line) + ": " +
                      message);
}

}  // namespace freeform
