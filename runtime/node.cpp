#include "runtime/node.hpp"

#include <stdexcept>

namespace gslift {

namespace {
template <class T>
const T& get_param(const GraphNode& node, const std::string& name) {
  auto it = node.params.find(name);
  if (it == node.params.end())
    throw std::logic_error("node '" + node.id + "' has no param '" + name + "'");
  if (const T* v = std::get_if<T>(&it->second)) return *v;
  throw std::logic_error("node '" + node.id + "': param '" + name + "' read with the wrong type");
}
}  // namespace

int64_t NodeContext::param_int(const std::string& n) const {
  return get_param<int64_t>(node(), n);
}
double NodeContext::param_float(const std::string& n) const {
  return get_param<double>(node(), n);
}
bool NodeContext::param_bool(const std::string& n) const {
  return get_param<bool>(node(), n);
}
const std::string& NodeContext::param_string(const std::string& n) const {
  return get_param<std::string>(node(), n);
}
const std::vector<double>& NodeContext::param_floats(const std::string& n) const {
  return get_param<std::vector<double>>(node(), n);
}
const std::vector<int64_t>& NodeContext::param_ints(const std::string& n) const {
  return get_param<std::vector<int64_t>>(node(), n);
}
const std::vector<std::string>& NodeContext::param_strings(const std::string& n) const {
  return get_param<std::vector<std::string>>(node(), n);
}

}  // namespace gslift
