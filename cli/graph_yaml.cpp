#include "cli/graph_yaml.hpp"

namespace gslift {

namespace {
// "{a: 1, b: \"x\"}": param values in their YAML-compatible rendering (param/param.hpp).
std::string flow_map(const std::map<std::string, ParamValue>& values) {
  std::string out;
  for (const auto& [k, v] : values) out += (out.empty() ? "" : ", ") + k + ": " + to_string(v);
  return "{" + out + "}";
}
}  // namespace

std::string graph_yaml(const Graph& graph) {
  std::string out = "graph: " + graph.name + "\n";
  if (!graph.params.empty()) out += "params: " + flow_map(graph.params) + "\n";
  out += "nodes:\n";
  for (const auto& n : graph.nodes) {
    out += "  " + n.id + ":\n    type: " + n.type + "\n";
    if (!n.inputs.empty()) {
      std::string in;
      for (const auto& [port, ref] : n.inputs)
        in += (in.empty() ? "" : ", ") + port + ": " + ref.str();
      out += "    in: {" + in + "}\n";
    }
    if (!n.params.empty()) out += "    params: " + flow_map(n.params) + "\n";
  }
  return out;
}

}  // namespace gslift
