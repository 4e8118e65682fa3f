#include "graph/set_override.hpp"

#include "base/utf8.hpp"
#include "graph/suggest.hpp"

namespace gslift {

namespace {

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t");
  const size_t e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

void apply_set(GraphDocument& doc, const std::string& set, Diagnostics& diagnostics) {
  // The whole --set is the location every diagnostic below prints: quoted like any input.
  const SourceLoc at{"--set " + printable(set), 0, 0};
  const size_t eq = set.find('=');
  const std::string key = trim(set.substr(0, eq));
  const size_t dot = key.find('.');
  if (eq == std::string::npos || key.empty() || dot == 0 || dot + 1 == key.size() ||
      (dot != std::string::npos && key.find('.', dot + 1) != std::string::npos)) {
    diagnostics.error(at, "bad-set",
                      "expected name=value, node.param=value, node.type=type or params.name=value");
    return;
  }
  // A name without a dot is a graph param, as with params.name.
  const std::string target = dot == std::string::npos ? "params" : key.substr(0, dot);
  const std::string name = dot == std::string::npos ? key : key.substr(dot + 1);
  YAML::Node value;
  try {
    value = YAML::Load(set.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    diagnostics.error(at, "bad-set", "the value is not a YAML scalar or flow list: " + e.msg);
    return;
  }
  if (target == "params") {
    auto p = doc.params.find(name);
    if (p == doc.params.end()) {
      std::vector<std::string> known;
      for (const auto& [k, v] : doc.params) known.push_back(k);
      diagnostics.error(at, "bad-set", "the graph has no param '" + printable(name) + "'",
                        suggest(name, known));
      return;
    }
    p->second = DocValue(value, at, at);
    return;
  }
  DocNode* node = doc.find(target);
  if (!node) {
    diagnostics.error(at, "bad-set", "the graph has no node '" + printable(target) + "'",
                      suggest(target, doc.node_ids()));
    return;
  }
  if (name == "type") {
    if (!value.IsScalar() || value.Scalar().empty()) {
      diagnostics.error(at, "bad-set", "a node type must be a single name, e.g. lifting.cvp");
      return;
    }
    DocNode over;
    over.id = node->id;
    over.loc = node->loc;
    over.type = value.Scalar();
    over.type_loc = at;
    merge_node(*node, over, diagnostics);
    return;
  }
  node->params[name] = DocValue(value, at, at);
}

}  // namespace

void apply_sets(GraphDocument& doc, const std::vector<std::string>& sets,
                Diagnostics& diagnostics) {
  for (const auto& set : sets) apply_set(doc, set, diagnostics);
}

}  // namespace gslift
