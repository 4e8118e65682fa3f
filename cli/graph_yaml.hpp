// `gslift validate --print`: a resolved graph (extends, ${} and --set applied, every default
// filled in) written back as a standalone YAML graph file that load_graph reads unchanged.
#pragma once

#include <string>

#include "graph/graph.hpp"

namespace gslift {

std::string graph_yaml(const Graph& graph);

}  // namespace gslift
