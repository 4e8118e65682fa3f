#include "cli/graph_file.hpp"

#include <cstdio>
#include <variant>
#include <vector>

#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "base/utf8.hpp"

namespace gslift {

namespace {

void print_diagnostics(const std::vector<Diagnostic>& diagnostics, std::set<std::string>* printed) {
  for (const auto& d : diagnostics) {
    const std::string text = d.str();
    if (printed && !printed->insert(text).second) continue;
    std::fprintf(stderr, "%s\n", terminal_safe(text).c_str());
  }
}

}  // namespace

std::optional<Graph> load_checked(const std::string& file, const Registry& registry,
                                  const LoadOptions& opt, std::set<std::string>* printed) {
  require_regular_file(file, "graph file");  // a directory, FIFO or symlink loop: exit 4
  LoadResult loaded = load_graph(file, registry, opt);
  print_diagnostics(loaded.diagnostics, printed);
  if (!loaded.ok()) {
    size_t errors = 0;
    for (const auto& d : loaded.diagnostics) errors += d.severity == Diagnostic::Severity::Error;
    std::fprintf(stderr, "%s: invalid graph (%zu error%s)\n", file.c_str(), errors,
                 errors == 1 ? "" : "s");
  }
  return std::move(loaded.graph);
}

uint64_t run_seed(const Graph& graph) {
  auto it = graph.params.find("seed");
  if (it == graph.params.end()) return 0;
  if (const int64_t* v = std::get_if<int64_t>(&it->second); v && *v >= 0)
    return static_cast<uint64_t>(*v);
  throw InputError("graph param 'seed' must be a non-negative integer, got " +
                   to_string(it->second));
}

}  // namespace gslift
