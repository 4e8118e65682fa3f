#include "runtime/registry.hpp"

#include <stdexcept>

namespace gslift {

void Registry::add(NodeSpec spec, NodeFn fn) {
  const std::string type = spec.type;
  if (entries_.count(type)) throw std::logic_error("node type '" + type + "' registered twice");
  for (const auto& p : spec.params) {
    if (!p.default_value) continue;
    const std::string err = check_param(p, *p.default_value);
    if (!err.empty())
      throw std::logic_error("node type '" + type + "': default of param '" + p.name + "': " + err);
  }
  entries_.emplace(type, Entry{std::move(spec), std::move(fn)});
}

const NodeSpec* Registry::find(const std::string& type) const {
  auto it = entries_.find(type);
  return it == entries_.end() ? nullptr : &it->second.spec;
}

std::vector<std::string> Registry::types() const {
  std::vector<std::string> out;
  for (const auto& [k, v] : entries_) out.push_back(k);
  return out;
}

const NodeFn& Registry::body(const std::string& type) const {
  auto it = entries_.find(type);
  if (it == entries_.end()) throw std::logic_error("unknown node type '" + type + "'");
  return it->second.fn;
}

}  // namespace gslift
