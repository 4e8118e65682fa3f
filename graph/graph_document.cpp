#include "graph/graph_document.hpp"

#include <algorithm>

#include "graph/suggest.hpp"

namespace gslift {

SourceLoc loc_of(const YAML::Node& node, const std::string& file) {
  const YAML::Mark m = node.Mark();
  if (m.line < 0) return SourceLoc{file, 0, 0};
  return SourceLoc{file, m.line + 1, m.column + 1};  // yaml-cpp marks are 0-based
}

DocValue::DocValue(YAML::Node v, SourceLoc key, SourceLoc at, std::filesystem::path folder)
    : value(std::move(v)),
      key_loc(std::move(key)),
      value_loc(std::move(at)),
      dir(std::move(folder)) {}

DocValue& DocValue::operator=(const DocValue& other) {
  value.reset(other.value);
  key_loc = other.key_loc;
  value_loc = other.value_loc;
  dir = other.dir;
  return *this;
}

DocNode* GraphDocument::find(const std::string& id) {
  for (auto& n : nodes)
    if (n.id == id) return &n;
  return nullptr;
}

std::vector<std::string> GraphDocument::node_ids() const {
  std::vector<std::string> ids;
  for (const auto& n : nodes) ids.push_back(n.id);
  return ids;
}

void merge_node(DocNode& node, const DocNode& over, Diagnostics& diagnostics) {
  node.loc = over.loc;
  if (!over.type.empty() && over.type != node.type) {
    if (!node.params.empty() && !node.type.empty()) {
      std::string dropped;
      for (const auto& [name, value] : node.params) dropped += (dropped.empty() ? "" : ", ") + name;
      diagnostics.warning(over.type_loc, "dropped-params",
                          "node '" + node.id + "' changes type from " + node.type + " to " +
                              over.type + "; its earlier params are dropped: " + dropped);
    }
    node.params.clear();
    for (const auto& [port, ref] : node.inputs) node.inputs_of_replaced_type.insert(port);
  }
  if (!over.type.empty()) {
    node.type = over.type;
    node.type_loc = over.type_loc;
  }
  for (const auto& [port, ref] : over.inputs) {
    if (ref.value.IsNull()) {
      // `port: null` unwires the base's input: a production graph's prompt file replaces the
      // evaluated graph's ground-truth masks this way.
      if (!node.inputs.count(port)) {
        std::vector<std::string> wired;
        for (const auto& [p, r] : node.inputs) wired.push_back(p);
        diagnostics.error(ref.key_loc, "nothing-to-remove",
                          "input '" + port + "' of node '" + node.id +
                              "' is declared null, but the base graph does not wire it",
                          suggest(port, wired));
      }
      node.inputs.erase(port);
      node.inputs_of_replaced_type.erase(port);
      continue;
    }
    node.inputs[port] = ref;
    node.inputs_of_replaced_type.erase(port);
  }
  for (const auto& [name, value] : over.params) node.params[name] = value;
  for (const auto& [key, value] : over.unknown_keys) node.unknown_keys[key] = value;
}

void merge_document(GraphDocument& base, const GraphDocument& derived, Diagnostics& diagnostics) {
  if (!derived.name.empty()) base.name = derived.name;
  base.files.insert(base.files.end(), derived.files.begin(), derived.files.end());
  for (const auto& [name, value] : derived.params) base.params[name] = value;
  for (const auto& node : derived.nodes) {
    if (node.removed) {
      const auto before = base.nodes.size();
      base.nodes.erase(std::remove_if(base.nodes.begin(), base.nodes.end(),
                                      [&](const DocNode& n) { return n.id == node.id; }),
                       base.nodes.end());
      if (base.nodes.size() == before)
        diagnostics.error(node.loc, "nothing-to-remove",
                          "node '" + node.id +
                              "' is declared null, but the base graph has no "
                              "such node to remove",
                          suggest(node.id, base.node_ids()));
      continue;
    }
    if (DocNode* existing = base.find(node.id))
      merge_node(*existing, node, diagnostics);
    else
      base.nodes.push_back(node);
  }
}

}  // namespace gslift
