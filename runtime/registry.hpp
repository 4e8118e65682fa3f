// The node registry: every node type's contract (NodeSpec) and the function that runs it.
// Built-in nodes are added by one explicit call, register_builtin_nodes (nodes/builtin.hpp), not
// by static initialisers, which a static library would silently drop.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "graph/node_spec.hpp"
#include "runtime/node.hpp"

namespace gslift {

class Registry : public NodeCatalog {
 public:
  // Throws std::logic_error on a duplicate type or an inconsistent spec (bad default, etc.).
  void add(NodeSpec spec, NodeFn fn);

  const NodeSpec* find(const std::string& type) const override;
  std::vector<std::string> types() const override;  // sorted
  const NodeFn& body(const std::string& type) const;

 private:
  struct Entry {
    NodeSpec spec;
    NodeFn fn;
  };
  std::map<std::string, Entry> entries_;
};

}  // namespace gslift
