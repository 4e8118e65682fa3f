// A resolved, validated pipeline: what `load_graph` produces from YAML (extends, ${} substitution
// and --set overrides already applied) and what the executor runs.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "param/param.hpp"

namespace gslift {

// A position in a YAML file, 1-based, for diagnostics ("graphs/langor.yaml:12:5").
struct SourceLoc {
  std::string file;
  int line = 0;
  int column = 0;
  std::string str() const;  // "file:line:col", or "file" when the line is unknown
};

struct PortRef {
  std::string node;  // producer node id
  std::string port;  // producer output port
  std::string str() const { return node + "." + port; }
};

struct GraphNode {
  std::string id;
  std::string type;
  std::map<std::string, PortRef> inputs;  // input port -> producer output
  // Every declared param of the type, defaults filled in, overrides applied.
  std::map<std::string, ParamValue> params;
  SourceLoc loc;                                // where the node is declared
  std::map<std::string, SourceLoc> param_locs;  // where each explicitly set param came from
};

struct Graph {
  std::string name;
  std::vector<std::string> files;            // the YAML files it was read from, base first
  std::map<std::string, ParamValue> params;  // graph-level params (${name} sources)
  std::vector<GraphNode> nodes;              // in topological order after validation

  const GraphNode* find(const std::string& id) const;
};

}  // namespace gslift
