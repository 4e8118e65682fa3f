// YAML -> validated Graph. Reads a graph file (following `extends:`), substitutes ${name} from
// graph params and the command line, applies --set overrides, fills defaults from the node
// catalog and validates everything before anything runs. All problems are collected, each with
// file:line:column, not only the first.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "graph/graph.hpp"
#include "graph/node_spec.hpp"

namespace gslift {

struct Diagnostic {
  enum class Severity { Error, Warning };
  Severity severity = Severity::Error;
  SourceLoc loc;
  std::string code;     // stable kind, e.g. "unknown-type", "cycle", "type-mismatch"
  std::string message;  // what is wrong, naming node/port/param
  std::string hint;     // e.g. "did you mean 'boxes.cluster'?"; may be empty
  // "file:line:col: error[code]: message (hint)" (warning[code] for warnings)
  std::string str() const;
};

struct LoadOptions {
  // ${name} values from the command line (e.g. input=<path> from --input); they win over the
  // graph's `params:` defaults.
  std::map<std::string, std::string> vars;
  // --set overrides, "node.param=value" (value parsed as YAML scalar or flow list) or
  // "node.type=other.type" to swap a stage; applied in order after the file is read.
  std::vector<std::string> sets;
};

struct LoadResult {
  std::optional<Graph> graph;  // set only when there is no error
  std::vector<Diagnostic> diagnostics;
  bool ok() const { return graph.has_value(); }
};

LoadResult load_graph(const std::filesystem::path& file, const NodeCatalog& catalog,
                      const LoadOptions& options = {});

// Same, from YAML text; `name` stands for the file in diagnostics and `base_dir` resolves extends.
LoadResult load_graph_text(const std::string& yaml, const std::string& name,
                           const NodeCatalog& catalog, const LoadOptions& options = {},
                           const std::filesystem::path& base_dir = {});

}  // namespace gslift
