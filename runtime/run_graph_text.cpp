// Kept apart from executor.cpp so that code running graphs it builds itself does not pull in the
// YAML loader.
#include <stdexcept>

#include "runtime/executor.hpp"

namespace gslift {

RunResult run_graph_text(const std::string& yaml, const Registry& registry,
                         const RunOptions& options, const LoadOptions& load) {
  const LoadResult loaded = load_graph_text(yaml, "<inline>", registry, load);
  if (!loaded.ok()) {
    std::string text = "invalid inline graph:";
    for (const auto& d : loaded.diagnostics) text += "\n" + d.str();
    throw std::invalid_argument(text);
  }
  return execute(*loaded.graph, registry, options);
}

}  // namespace gslift
