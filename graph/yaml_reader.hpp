// Reading graph YAML into a GraphDocument: syntax errors, duplicate keys (which yaml-cpp 0.7
// accepts silently), unknown keys, malformed ids and the `extends:` chain.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "graph/diagnostics.hpp"
#include "graph/graph_document.hpp"

namespace gslift {

// Reads `text` (standing for the file `name` in diagnostics) and, first, the file it extends,
// resolved against `base_dir`. Returns nullopt when the YAML cannot be read at all; structural
// problems are reported to `diagnostics` and the rest of the document is still read.
std::optional<GraphDocument> read_graph_yaml(const std::string& text, const std::string& name,
                                             const std::filesystem::path& base_dir,
                                             Diagnostics& diagnostics);

// Same for a file on disk; a file that cannot be opened is an `unreadable-file` error.
std::optional<GraphDocument> read_graph_file(const std::filesystem::path& file,
                                             Diagnostics& diagnostics);

}  // namespace gslift
