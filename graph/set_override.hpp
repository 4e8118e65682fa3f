// --set overrides from the command line, applied in order after the files are read:
//   node.param=value   a node param; value is a YAML scalar or flow list ("0.7", "[1, 2]", "text")
//   node.type=a.type   swaps the node's type; its params restart (as in a derived file)
//   name=value         a graph param (a ${name} source); params.name=value says the same
// Each value's diagnostics point at the pseudo-location "--set <text>".
#pragma once

#include <string>
#include <vector>

#include "graph/diagnostics.hpp"
#include "graph/graph_document.hpp"

namespace gslift {

// Reports `bad-set` for a malformed override or one naming a missing node or graph param (with
// the nearest name as hint); unknown node params are left to validation (`unknown-param`).
void apply_sets(GraphDocument& doc, const std::vector<std::string>& sets, Diagnostics& diagnostics);

}  // namespace gslift
