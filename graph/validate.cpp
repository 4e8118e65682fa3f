#include "graph/validate.hpp"

#include <algorithm>
#include <filesystem>
#include <regex>
#include <set>

#include "base/utf8.hpp"
#include "graph/suggest.hpp"
#include "graph/yaml_param.hpp"

namespace gslift {

namespace {

template <class T>
std::vector<std::string> names_of(const std::vector<T>& specs) {
  std::vector<std::string> names;
  for (const auto& s : specs) names.push_back(s.name);
  return names;
}

// A path param's value written in a graph file: a relative path becomes absolute against the
// file's folder `dir`, like `extends:`. Kept as it is: an empty value, an absolute path, a value
// with a scheme ("embedded:or", "https://...": two or more letters before the colon, so a drive
// letter stays a path) and any value without a folder (command line, text read without one).
std::string resolve_path(const std::string& value, const std::filesystem::path& dir) {
  static const std::regex scheme("[A-Za-z][A-Za-z0-9+.-]+:.*");
  if (dir.empty() || value.empty() || std::regex_match(value, scheme)) return value;
  const std::filesystem::path p(value);
  if (p.is_absolute()) return value;
  return std::filesystem::absolute(dir / p).lexically_normal().string();
}

std::string describe(const DocNode& node) {
  return "node '" + printable(node.id) + "' (" + printable(node.type) + ")";
}

// A resolved input edge: `producer`'s output `out_port` feeds `consumer`'s input `port`.
struct Edge {
  size_t consumer;
  std::string port;
  size_t producer;
  std::string out_port;
};

// The checks against the catalog, in three steps that build on each other: resolve_nodes
// (types, params, inputs; records the edges), topological_order (Kahn, cycles), then
// report_unused_outputs.
class Validator {
 public:
  Validator(const GraphDocument& doc, const NodeCatalog& catalog, Diagnostics& diagnostics)
      : doc_(doc), catalog_(catalog), diagnostics_(diagnostics) {
    for (size_t i = 0; i < doc.nodes.size(); ++i) index_[doc.nodes[i].id] = i;
    for (const auto& node : doc.nodes) specs_.push_back(find_spec(node));
  }

  std::vector<GraphNode> resolve_nodes() {
    std::vector<GraphNode> nodes;
    for (size_t i = 0; i < doc_.nodes.size(); ++i) {
      const DocNode& doc_node = doc_.nodes[i];
      GraphNode node;
      node.id = doc_node.id;
      node.type = doc_node.type;
      node.loc = doc_node.loc;
      report_unknown_keys(doc_node, specs_[i]);
      if (specs_[i]) resolve_params(doc_node, *specs_[i], node);
      resolve_inputs(i, node);
      nodes.push_back(std::move(node));
    }
    return nodes;
  }

  // Kahn's algorithm over the resolved edges, the ready node declared first going first; the
  // nodes left over lie on or downstream of cycles, which are reported.
  std::vector<size_t> topological_order() {
    const size_t n = doc_.nodes.size();
    std::vector<size_t> in_degree(n, 0);
    std::vector<std::vector<size_t>> consumers(n);
    for (const auto& e : edges_) {
      ++in_degree[e.consumer];
      consumers[e.producer].push_back(e.consumer);
    }
    std::set<size_t> ready;
    for (size_t i = 0; i < n; ++i)
      if (in_degree[i] == 0) ready.insert(i);
    std::vector<size_t> order;
    while (!ready.empty()) {
      const size_t i = *ready.begin();
      ready.erase(ready.begin());
      order.push_back(i);
      for (size_t c : consumers[i])
        if (--in_degree[c] == 0) ready.insert(c);
    }
    if (order.size() < n) report_cycles(in_degree);
    return order;
  }

  void report_unused_outputs() {
    std::vector<std::set<std::string>> consumed(doc_.nodes.size());
    for (const auto& e : edges_) consumed[e.producer].insert(e.out_port);
    for (size_t i = 0; i < doc_.nodes.size(); ++i) {
      if (!specs_[i] || consumed[i].empty()) continue;
      std::string unused;
      for (const auto& out : specs_[i]->outputs)
        if (!consumed[i].count(out.name)) unused += (unused.empty() ? "" : ", ") + out.name;
      if (!unused.empty())
        diagnostics_.warning(doc_.nodes[i].loc, "unused-output",
                             describe(doc_.nodes[i]) + " has outputs no node consumes: " + unused);
    }
  }

 private:
  const NodeSpec* find_spec(const DocNode& node) {
    if (node.type.empty()) {
      diagnostics_.error(node.loc, "missing-type", "node '" + printable(node.id) + "' has no type");
      return nullptr;
    }
    const NodeSpec* spec = catalog_.find(node.type);
    if (!spec)
      diagnostics_.error(
          node.type_loc, "unknown-type",
          "node '" + printable(node.id) + "' has unknown type '" + printable(node.type) + "'",
          unknown_type_hint(node.type));
    return spec;
  }

  void report_unknown_keys(const DocNode& node, const NodeSpec* spec) {
    for (const auto& [key, value] : node.unknown_keys) {
      std::string hint = suggest(key, {"type", "in", "params"}, true);
      if (spec && spec->find_param(key))
        hint = "'" + key + "' is a param of " + node.type + ": write it under params:";
      else if (spec && spec->find_input(key))
        hint = "'" + key + "' is an input of " + node.type + ": write it under in:";
      diagnostics_.error(
          value.key_loc, "unknown-key",
          "unknown key '" + printable(key) + "' in node '" + printable(node.id) + "'", hint);
    }
  }

  void resolve_params(const DocNode& doc_node, const NodeSpec& spec, GraphNode& node) {
    for (const auto& [name, given] : doc_node.params) {
      const ParamSpec* param = spec.find_param(name);
      if (!param) {
        diagnostics_.error(given.key_loc, "unknown-param",
                           describe(doc_node) + " has no param '" + printable(name) + "'",
                           suggest(name, names_of(spec.params), true));
        continue;
      }
      std::string error;
      auto value = param_from_yaml(given.value, param->type, error);
      if (!value) {
        diagnostics_.error(given.value_loc, "param-type",
                           "param '" + name + "' of " + describe(doc_node) + ": " + error);
        continue;
      }
      if (auto bad = check_param(*param, *value); !bad.empty()) {
        diagnostics_.error(given.value_loc, "param-range",
                           "param '" + name + "' of " + describe(doc_node) + ": " + bad);
        continue;
      }
      if (param->path)
        if (auto* text = std::get_if<std::string>(&*value)) *text = resolve_path(*text, given.dir);
      node.params[name] = *value;
      node.param_locs[name] = given.value_loc;
    }
    // A preset (ParamSpec::presets) sets the params the file leaves unset; a param the file sets
    // keeps its value.
    for (const auto& param : spec.params) {
      if (param.presets.empty()) continue;
      const auto chosen = node.params.find(param.name);
      const ParamValue* value = chosen != node.params.end() ? &chosen->second
                                : param.default_value       ? &*param.default_value
                                                            : nullptr;
      const auto* choice = value ? std::get_if<std::string>(value) : nullptr;
      const auto preset = choice ? param.presets.find(*choice) : param.presets.end();
      if (preset == param.presets.end()) continue;
      for (const auto& [name, set] : preset->second)
        if (!doc_node.params.count(name)) node.params[name] = set;
    }
    for (const auto& param : spec.params) {
      if (doc_node.params.count(param.name) || node.params.count(param.name)) continue;
      if (param.default_value)
        node.params[param.name] = *param.default_value;
      else
        diagnostics_.error(doc_node.loc, "missing-param",
                           describe(doc_node) + " needs param '" + param.name + "' (" +
                               to_string(param.type) + "): " + param.doc);
    }
  }

  void resolve_inputs(size_t consumer, GraphNode& node) {
    const DocNode& doc_node = doc_.nodes[consumer];
    const NodeSpec* spec = specs_[consumer];
    std::set<std::string> wired;
    for (const auto& [port, ref] : doc_node.inputs) {
      const PortSpec* in = spec ? spec->find_input(port) : nullptr;
      if (spec && !in) {
        if (doc_node.inputs_of_replaced_type.count(port)) {
          diagnostics_.warning(ref.key_loc, "dropped-inputs",
                               describe(doc_node) + " has no input '" + printable(port) +
                                   "'; the input wired for its earlier type is dropped");
        } else {
          diagnostics_.error(ref.key_loc, "unknown-input-port",
                             describe(doc_node) + " has no input '" + printable(port) + "'",
                             suggest(port, names_of(spec->inputs), true));
        }
        continue;
      }
      wired.insert(port);
      if (auto producer = resolve_reference(consumer, port, in, ref)) {
        node.inputs[port] = PortRef{doc_.nodes[producer->first].id, producer->second};
        edges_.push_back(Edge{consumer, port, producer->first, producer->second});
      }
    }
    if (!spec) return;
    for (const auto& in : spec->inputs) {
      if (!in.optional && !wired.count(in.name))
        diagnostics_.error(doc_node.loc, "missing-input",
                           describe(doc_node) + " needs input '" + in.name + "' (" + in.type + ")",
                           outputs_of_type(in.type, consumer));
      if (!wired.count(in.name)) continue;
      for (const auto& other : in.wired_with) {
        const PortSpec* partner = spec->find_input(other);
        if (wired.count(other) || !partner) continue;
        diagnostics_.error(doc_node.inputs.at(in.name).key_loc, "missing-input",
                           describe(doc_node) + " input '" + in.name + "' needs input '" + other +
                               "' (" + partner->type + ") wired with it",
                           outputs_of_type(partner->type, consumer));
      }
    }
  }

  // Checks `ref` ("node.port") wired to input `port` (spec `in`, null when unknown); returns the
  // producer's index and output port when the reference resolves.
  std::optional<std::pair<size_t, std::string>> resolve_reference(size_t consumer_index,
                                                                  const std::string& port,
                                                                  const PortSpec* in,
                                                                  const DocValue& ref) {
    const DocNode& consumer = doc_.nodes[consumer_index];
    const std::string text = ref.value.IsScalar() ? ref.value.Scalar() : std::string();
    const size_t dot = text.find('.');
    if (dot == std::string::npos || dot == 0 || dot + 1 == text.size() ||
        text.find('.', dot + 1) != std::string::npos) {
      diagnostics_.error(ref.value_loc, "bad-reference",
                         "input '" + printable(port) + "' of node '" + printable(consumer.id) +
                             "' must be of the form node.port, got '" + printable(text) + "'");
      return std::nullopt;
    }
    const std::string producer_id = text.substr(0, dot);
    const std::string out_port = text.substr(dot + 1);
    const auto producer = index_.find(producer_id);
    if (producer == index_.end()) {
      diagnostics_.error(ref.value_loc, "unknown-node",
                         "input '" + printable(port) + "' of node '" + printable(consumer.id) +
                             "' refers to missing node '" + printable(producer_id) + "'",
                         suggest(producer_id, doc_.node_ids()));
      return std::nullopt;
    }
    const NodeSpec* producer_spec = specs_[producer->second];
    if (!producer_spec) return std::make_pair(producer->second, out_port);
    const PortSpec* out = producer_spec->find_output(out_port);
    if (!out) {
      diagnostics_.error(ref.value_loc, "unknown-output-port",
                         "input '" + printable(port) + "' of node '" + printable(consumer.id) +
                             "' refers to '" + printable(text) + "', but " +
                             describe(doc_.nodes[producer->second]) + " has no output '" +
                             printable(out_port) + "'",
                         suggest(out_port, names_of(producer_spec->outputs), true));
      return std::nullopt;
    }
    if (in && in->type != out->type)
      diagnostics_.error(ref.value_loc, "type-mismatch",
                         "input '" + printable(port) + "' of " + describe(consumer) + " takes " +
                             in->type + ", but '" + printable(text) + "' of " +
                             describe(doc_.nodes[producer->second]) + " gives " + out->type,
                         outputs_of_type(in->type, consumer_index));
    return std::make_pair(producer->second, out_port);
  }

  std::string unknown_type_hint(const std::string& type) const {
    const std::string near = suggest(type, catalog_.types());
    return near.empty() ? "`gslift nodes` lists the types" : near;
  }

  // A hint naming the outputs in the graph that give `type` (not `except`'s own), at most five:
  // "outputs of type Number: one.value, sum.sum".
  std::string outputs_of_type(const std::string& type, size_t except) const {
    std::vector<std::string> found;
    for (size_t i = 0; i < doc_.nodes.size(); ++i)
      if (i != except && specs_[i])
        for (const auto& out : specs_[i]->outputs)
          if (out.type == type) found.push_back(doc_.nodes[i].id + "." + out.name);
    if (found.empty()) return {};
    std::string hint = "outputs of type " + type + ":";
    for (size_t i = 0; i < found.size() && i < 5; ++i) hint += (i ? ", " : " ") + found[i];
    return found.size() > 5 ? hint + ", ..." : hint;
  }

  // Every node left by Kahn's algorithm has a producer that was left too; following producers
  // from any of them therefore ends in a cycle. Each distinct cycle is reported once, in data
  // flow order, starting at its earliest declared node: "a -> b -> c -> a".
  void report_cycles(const std::vector<size_t>& in_degree) {
    std::vector<std::vector<size_t>> producers(doc_.nodes.size());
    for (const auto& e : edges_)
      if (in_degree[e.producer] > 0) producers[e.consumer].push_back(e.producer);
    std::set<std::vector<size_t>> reported;
    for (size_t start = 0; start < doc_.nodes.size(); ++start) {
      if (in_degree[start] == 0) continue;
      std::vector<size_t> path{start};
      size_t next = producers[start].front();
      while (std::find(path.begin(), path.end(), next) == path.end()) {
        path.push_back(next);
        next = producers[next].front();
      }
      std::vector<size_t> cycle(std::find(path.begin(), path.end(), next), path.end());
      std::reverse(cycle.begin(), cycle.end());  // producers were followed: flip to data flow
      std::rotate(cycle.begin(), std::min_element(cycle.begin(), cycle.end()), cycle.end());
      if (!reported.insert(cycle).second) continue;
      std::string names;
      for (size_t i : cycle) names += doc_.nodes[i].id + " -> ";
      diagnostics_.error(doc_.nodes[cycle.front()].loc, "cycle",
                         "the graph has a cycle: " + names + doc_.nodes[cycle.front()].id);
    }
  }

  const GraphDocument& doc_;
  const NodeCatalog& catalog_;
  Diagnostics& diagnostics_;
  std::map<std::string, size_t> index_;
  std::vector<const NodeSpec*> specs_;
  std::vector<Edge> edges_;
};

std::map<std::string, ParamValue> graph_params(const GraphDocument& doc,
                                               const std::map<std::string, std::string>& vars,
                                               Diagnostics& diagnostics) {
  std::map<std::string, ParamValue> params;
  std::string error;
  for (const auto& [name, given] : doc.params) {
    if (given.value.IsNull()) continue;  // unset: refused where substituted (substitute.cpp)
    if (auto value = infer_param(given.value, error))
      params[name] = *value;
    else
      diagnostics.error(given.value_loc, "param-type", "graph param '" + name + "': " + error);
  }
  for (const auto& [name, text] : vars)
    if (auto value = infer_param(YAML::Node(text), error)) params[name] = *value;
  return params;
}

}  // namespace

std::optional<Graph> validate_graph(const GraphDocument& doc, const NodeCatalog& catalog,
                                    const std::map<std::string, std::string>& vars,
                                    Diagnostics& diagnostics) {
  Graph graph;
  graph.files = doc.files;
  graph.name = !doc.name.empty() || doc.files.empty()
                   ? doc.name
                   : std::filesystem::path(doc.files.back()).stem().string();
  graph.params = graph_params(doc, vars, diagnostics);
  if (doc.nodes.empty())
    diagnostics.error(SourceLoc{doc.files.empty() ? "" : doc.files.back(), 0, 0}, "schema",
                      "the graph has no nodes");
  Validator validator(doc, catalog, diagnostics);
  std::vector<GraphNode> nodes = validator.resolve_nodes();
  const std::vector<size_t> order = validator.topological_order();
  validator.report_unused_outputs();
  if (diagnostics.has_errors()) return std::nullopt;
  for (size_t i : order) graph.nodes.push_back(std::move(nodes[i]));
  return graph;
}

}  // namespace gslift
