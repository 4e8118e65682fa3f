#include "graph/loader.hpp"

#include "graph/diagnostics.hpp"
#include "graph/set_override.hpp"
#include "graph/substitute.hpp"
#include "graph/validate.hpp"
#include "graph/yaml_reader.hpp"

namespace gslift {

namespace {

// The stages after reading, in the order their effects stack: --set overrides apply to the
// merged files, ${} then sees the final graph params, validation sees the final values.
LoadResult finish(std::optional<GraphDocument> doc, const NodeCatalog& catalog,
                  const LoadOptions& options, Diagnostics& diagnostics) {
  LoadResult result;
  if (doc) {
    apply_sets(*doc, options.sets, diagnostics);
    substitute_vars(*doc, options.vars, diagnostics);
    auto graph = validate_graph(*doc, catalog, options.vars, diagnostics);
    if (!diagnostics.has_errors()) result.graph = std::move(graph);
  }
  result.diagnostics = diagnostics.list();
  return result;
}

}  // namespace

LoadResult load_graph(const std::filesystem::path& file, const NodeCatalog& catalog,
                      const LoadOptions& options) {
  Diagnostics diagnostics;
  auto doc = read_graph_file(file, diagnostics);
  return finish(std::move(doc), catalog, options, diagnostics);
}

LoadResult load_graph_text(const std::string& yaml, const std::string& name,
                           const NodeCatalog& catalog, const LoadOptions& options,
                           const std::filesystem::path& base_dir) {
  Diagnostics diagnostics;
  auto doc = read_graph_yaml(yaml, name, base_dir, diagnostics);
  return finish(std::move(doc), catalog, options, diagnostics);
}

}  // namespace gslift
