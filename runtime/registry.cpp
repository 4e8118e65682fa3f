#include "runtime/registry.hpp"

#include <stdexcept>

namespace gslift {

namespace {

// The registering file relative to the repository root: compilers (and ccache's base_dir) give
// it absolute or relative to the build folder.
std::string repository_path(std::string file) {
  const std::string root = std::string(GSLIFT_SOURCE_DIR) + "/";
  if (file.compare(0, root.size(), root) == 0) return file.substr(root.size());
  while (file.compare(0, 3, "../") == 0 || file.compare(0, 2, "./") == 0)
    file.erase(0, file[1] == '/' ? 2 : 3);
  return file;
}

}  // namespace

void Registry::add(NodeSpec spec, NodeFn fn, const char* source) {
  const std::string type = spec.type;

  if (entries_.count(type)) throw std::logic_error("node type '" + type + "' registered twice");
  for (const auto& p : spec.params) {
    if (!p.default_value) continue;
    const std::string err = check_param(p, *p.default_value);
    if (!err.empty())
      throw std::logic_error("node type '" + type + "': default of param '" + p.name + "': " + err);
  }
  // A preset names params of this node, with values they accept.
  for (const auto& p : spec.params)
    for (const auto& [choice, values] : p.presets)
      for (const auto& [name, value] : values) {
        const ParamSpec* target = spec.find_param(name);
        const std::string err = target ? check_param(*target, value) : "no such param";
        if (!err.empty())
          throw std::logic_error("node type '" + type + "': preset '" + choice + "' of param '" +
                                 p.name + "' sets '" + name + "': " + err);
      }
  entries_.emplace(type, Entry{std::move(spec), std::move(fn), repository_path(source)});
}

const PortCodec* Registry::codec(const std::string& port_type) const {
  auto it = codecs_.find(port_type);
  return it == codecs_.end() ? nullptr : &it->second;
}

void Registry::add_capture_probe(const std::string& type, CaptureProbe probe) {
  if (!entries_.count(type))
    throw std::logic_error("capture probe for unregistered node type '" + type + "'");
  probes_[type] = std::move(probe);
}

const Registry::CaptureProbe* Registry::capture_probe(const std::string& type) const {
  auto it = probes_.find(type);
  return it == probes_.end() ? nullptr : &it->second;
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

const std::string& Registry::source(const std::string& type) const {
  auto it = entries_.find(type);
  if (it == entries_.end()) throw std::logic_error("unknown node type '" + type + "'");
  return it->second.source;
}

const NodeFn& Registry::body(const std::string& type) const {
  auto it = entries_.find(type);
  if (it == entries_.end()) throw std::logic_error("unknown node type '" + type + "'");
  return it->second.fn;
}

}  // namespace gslift
