// Errors that algorithms throw. This header depends on nothing but the standard library, so an
// algorithm (a plain function over plain data) reports bad input without knowing the runtime that
// catches it; runtime/node.hpp includes it, so every catch site sees the same type.
#pragma once

#include <stdexcept>

namespace gslift {

// Thrown for bad input data (unreadable file, wrong size, ...). The runtime reports it with the
// node id, type and YAML line, and the CLI exits with the "unreadable input" code.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Thrown when results cannot be written (disk full, read-only or unwritable folder): the message
// names the file or folder and the system's reason. The CLI exits with the "cannot write" code,
// which a scheduler should not retry before someone frees space or fixes permissions.
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace gslift
