#include "graph/node_spec.hpp"

namespace gslift {

namespace {
template <class T>
const T* find_named(const std::vector<T>& v, const std::string& name) {
  for (const auto& x : v)
    if (x.name == name) return &x;
  return nullptr;
}
}  // namespace

const PortSpec* NodeSpec::find_input(const std::string& n) const {
  return find_named(inputs, n);
}
const PortSpec* NodeSpec::find_output(const std::string& n) const {
  return find_named(outputs, n);
}
const ParamSpec* NodeSpec::find_param(const std::string& n) const {
  return find_named(params, n);
}

}  // namespace gslift
