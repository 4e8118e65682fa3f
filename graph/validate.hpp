// Checking a GraphDocument against the node catalog and resolving it into a Graph: node types,
// params (typed, range-checked, defaults filled), inputs (references, port names, port types),
// cycles, then the nodes in topological order.
#pragma once

#include <map>
#include <optional>
#include <string>

#include "graph/diagnostics.hpp"
#include "graph/graph_document.hpp"
#include "graph/node_spec.hpp"

namespace gslift {

// Reports every problem to `diagnostics`; returns the Graph only when there is no error.
// Graph::params holds the graph params and `vars` (which win), typed from their YAML.
// Graph::nodes are in Kahn order, ties broken by declaration order. Warnings: `unused-output`
// for a node with some outputs consumed and others not (terminal nodes, with none consumed, are
// not reported); `dropped-inputs` for inputs kept from a replaced type that the new type lacks.
std::optional<Graph> validate_graph(const GraphDocument& doc, const NodeCatalog& catalog,
                                    const std::map<std::string, std::string>& vars,
                                    Diagnostics& diagnostics);

}  // namespace gslift
