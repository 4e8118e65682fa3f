#include "graph/yaml_reader.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "base/utf8.hpp"
#include "graph/suggest.hpp"

namespace gslift {

namespace {

namespace fs = std::filesystem;

using Entries = std::vector<std::pair<YAML::Node, YAML::Node>>;

// A map's entries in file order, each key once (the first wins; check_values reports
// the others).
Entries unique_entries(const YAML::Node& map) {
  Entries out;
  std::set<std::string> seen;
  for (auto it = map.begin(); it != map.end(); ++it)
    if (seen.insert(it->first.Scalar()).second) out.emplace_back(it->first, it->second);
  return out;
}

// A graph file expands to at most this many YAML values (scalars, lists, maps), aliases
// expanded: yaml-cpp shares an aliased node, but everything that walks the document (this check,
// the params, the merge with a base) visits it once per alias, so a 557-byte file of nested
// aliases ("billion laughs", 10x per level) kept `validate` busy for minutes. The graphs shipped
// in graphs/ hold a few hundred values; a generated sweep with thousands of nodes stays far below.
constexpr size_t kMaxYamlValues = 100000;

// What one walk of a document has seen: values so far, and whether it stopped at the budget.
struct Walk {
  size_t values = 0;
  bool over_budget = false;
};

// yaml-cpp 0.7 keeps every entry of a map, duplicates included, and node["key"] returns the
// first: walk every map and report each repeated key where it repeats. `what` names the keys
// ("node id" for the entries of the top-level `nodes:`). `ancestors` stops the walk at an alias
// of an enclosing node (`&x [1, *x]`), which yaml-cpp builds as a recursive structure. The same
// walk bounds the expanded size (kMaxYamlValues) and refuses NUL bytes in scalars, which would
// cut every message and path built from them short (C strings end there).
void check_values(const YAML::Node& node, const std::string& file, const std::string& what,
                  std::vector<YAML::Node>& ancestors, Walk& walk, Diagnostics& diagnostics) {
  if (walk.over_budget) return;
  if (++walk.values > kMaxYamlValues) {
    walk.over_budget = true;
    diagnostics.error(loc_of(node, file), "too-large",
                      "the graph file expands to more than " + std::to_string(kMaxYamlValues) +
                          " values here (nested YAML aliases?); refusing to expand it");
    return;
  }
  if (node.IsScalar() && node.Scalar().find('\0') != std::string::npos)
    diagnostics.error(loc_of(node, file), "schema", "a value may not contain a NUL byte");
  if (!node.IsMap() && !node.IsSequence()) return;
  for (const auto& a : ancestors)
    if (a.is(node)) {
      diagnostics.error(loc_of(node, file), "schema", "a value may not contain an alias of itself");
      return;
    }
  ancestors.push_back(node);
  if (node.IsSequence())
    for (const auto& e : node) check_values(e, file, "key", ancestors, walk, diagnostics);
  std::map<std::string, SourceLoc> seen;
  for (auto it = node.begin(); node.IsMap() && it != node.end() && !walk.over_budget; ++it) {
    check_values(it->first, file, "key", ancestors, walk, diagnostics);
    const std::string key = it->first.Scalar();
    const SourceLoc at = loc_of(it->first, file);
    if (auto [first, inserted] = seen.emplace(key, at); !inserted)
      diagnostics.error(at, "duplicate-key", "duplicate " + what + " '" + printable(key) + "'",
                        "first defined at line " + std::to_string(first->second.line));
    const bool node_ids = ancestors.size() == 1 && key == "nodes";
    check_values(it->second, file, node_ids ? "node id" : "key", ancestors, walk, diagnostics);
  }
  ancestors.pop_back();
}

bool is_node_id(const std::string& s) {
  static const std::regex re("[a-z][a-z0-9_]*");
  return std::regex_match(s, re);
}

bool is_param_name(const std::string& s) {
  static const std::regex re("[A-Za-z_][A-Za-z0-9_]*");
  return std::regex_match(s, re);
}

// Whether `value` is a map; a `schema` error when it is not.
bool expect_map(const YAML::Node& value, const std::string& what, const std::string& file,
                Diagnostics& diagnostics) {
  if (value.IsMap()) return true;
  diagnostics.error(loc_of(value, file), "schema", what + " must be a map");
  return false;
}

// The text of a scalar; a `schema` error for a list, map or null.
std::optional<std::string> scalar_text(const YAML::Node& value, const std::string& what,
                                       const std::string& file, Diagnostics& diagnostics) {
  if (value.IsScalar()) return value.Scalar();
  diagnostics.error(loc_of(value, file), "schema", what + " must be a single name");
  return std::nullopt;
}

DocNode read_node(const YAML::Node& key, const YAML::Node& value, const std::string& file,
                  const fs::path& dir, Diagnostics& diagnostics) {
  DocNode node;
  node.id = key.Scalar();
  node.loc = loc_of(key, file);
  if (!is_node_id(node.id))
    diagnostics.error(node.loc, "bad-id",
                      "node id '" + printable(node.id) + "' is not of the form [a-z][a-z0-9_]*");
  else if (node.id == "params")
    diagnostics.error(node.loc, "bad-id",
                      "node id 'params' is reserved: --set params.NAME=VALUE sets graph params");
  if (value.IsNull()) {  // removes a base's node (merge_document); alone, removes nothing
    node.removed = true;
    return node;
  }
  if (!expect_map(value, "node '" + printable(node.id) + "'", file, diagnostics)) return node;
  const std::string where = "node '" + printable(node.id) + "'";
  for (const auto& [k, v] : unique_entries(value)) {
    const std::string name = k.Scalar();
    if (name == "type") {
      if (auto t = scalar_text(v, "the type of " + where, file, diagnostics)) {
        node.type = *t;
        node.type_loc = loc_of(v, file);
      }
    } else if (name == "in") {
      if (!expect_map(v, "'in' of " + where, file, diagnostics)) continue;
      for (const auto& [port, ref] : unique_entries(v))
        node.inputs[port.Scalar()] = DocValue(ref, loc_of(port, file), loc_of(ref, file));
    } else if (name == "params") {
      if (!expect_map(v, "'params' of " + where, file, diagnostics)) continue;
      for (const auto& [param, pv] : unique_entries(v))
        node.params[param.Scalar()] = DocValue(pv, loc_of(param, file), loc_of(pv, file), dir);
    } else {
      node.unknown_keys[name] = DocValue(v, loc_of(k, file), loc_of(v, file));
    }
  }
  return node;
}

std::optional<std::string> read_text(const fs::path& file) {
  std::error_code ec;
  // A directory opens, then reads ""; a FIFO blocks; /dev/zero never ends.
  if (!fs::is_regular_file(file, ec)) return std::nullopt;
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::optional<GraphDocument> read(const std::string& text, const std::string& name,
                                  const fs::path& base_dir, std::vector<fs::path>& chain,
                                  Diagnostics& diagnostics);

// The document `extends: <value>` names, read relative to `base_dir`; nullopt (reported) when
// it cannot be read or would extend itself.
std::optional<GraphDocument> read_base(const YAML::Node& value, const std::string& name,
                                       const fs::path& base_dir, std::vector<fs::path>& chain,
                                       Diagnostics& diagnostics) {
  const auto rel = scalar_text(value, "'extends' (the base file)", name, diagnostics);
  if (!rel) return std::nullopt;
  const fs::path base_file = (base_dir / *rel).lexically_normal();
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(base_file, ec);
  if (std::find(chain.begin(), chain.end(), canonical) != chain.end()) {
    std::string cycle;
    for (const auto& f : chain) cycle += f.string() + " -> ";
    diagnostics.error(loc_of(value, name), "extends-cycle",
                      "extends cycle: " + cycle + canonical.string());
    return std::nullopt;
  }
  const auto base_text = read_text(base_file);
  if (!base_text) {
    diagnostics.error(loc_of(value, name), "unreadable-file",
                      "cannot read base graph " + base_file.string());
    return std::nullopt;
  }
  chain.push_back(canonical);
  auto base = read(*base_text, base_file.string(), base_file.parent_path(), chain, diagnostics);
  chain.pop_back();
  return base;
}

std::optional<GraphDocument> read(const std::string& text, const std::string& name,
                                  const fs::path& base_dir, std::vector<fs::path>& chain,
                                  Diagnostics& diagnostics) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    diagnostics.error(SourceLoc{name, e.mark.line + 1, e.mark.column + 1}, "yaml-syntax", e.msg);
    return std::nullopt;
  }
  if (!root.IsMap()) {
    diagnostics.error(loc_of(root, name), "schema",
                      "a graph file must be a map with keys graph, params, nodes, extends");
    return std::nullopt;
  }
  std::vector<YAML::Node> ancestors;
  Walk walk;
  check_values(root, name, "key", ancestors, walk, diagnostics);
  if (walk.over_budget) return std::nullopt;

  GraphDocument own;
  own.files.push_back(name);
  std::optional<GraphDocument> base;
  bool base_failed = false;
  for (const auto& [k, v] : unique_entries(root)) {
    const std::string key = k.Scalar();
    if (key == "graph") {
      if (auto s = scalar_text(v, "'graph' (the graph name)", name, diagnostics)) own.name = *s;
    } else if (key == "params") {
      if (!expect_map(v, "'params'", name, diagnostics)) continue;
      for (const auto& [pk, pv] : unique_entries(v)) {
        if (!is_param_name(pk.Scalar()))
          diagnostics.error(loc_of(pk, name), "bad-id",
                            "graph param '" + printable(pk.Scalar()) +
                                "' is not of the form [A-Za-z_][A-Za-z0-9_]*");
        own.params[pk.Scalar()] = DocValue(pv, loc_of(pk, name), loc_of(pv, name), base_dir);
      }
    } else if (key == "nodes") {
      if (!expect_map(v, "'nodes'", name, diagnostics)) continue;
      for (const auto& [nk, nv] : unique_entries(v))
        own.nodes.push_back(read_node(nk, nv, name, base_dir, diagnostics));
    } else if (key == "extends") {
      base = read_base(v, name, base_dir, chain, diagnostics);
      base_failed = !base;
    } else {
      diagnostics.error(loc_of(k, name), "unknown-key",
                        "unknown key '" + printable(key) + "' in the graph file",
                        suggest(key, {"graph", "params", "nodes", "extends"}, true));
    }
  }
  // Without its base a derived file is incomplete: checking it alone would only add noise.
  if (base_failed) return std::nullopt;
  if (!base) {
    for (const auto& node : own.nodes)
      if (node.removed)
        diagnostics.error(node.loc, "nothing-to-remove",
                          "node '" + node.id +
                              "' is declared null, which removes a base graph's "
                              "node, but this file extends none");
    own.nodes.erase(std::remove_if(own.nodes.begin(), own.nodes.end(),
                                   [](const DocNode& n) { return n.removed; }),
                    own.nodes.end());
    return own;
  }
  merge_document(*base, own, diagnostics);
  return base;
}

}  // namespace

std::optional<GraphDocument> read_graph_yaml(const std::string& text, const std::string& name,
                                             const std::filesystem::path& base_dir,
                                             Diagnostics& diagnostics) {
  std::vector<fs::path> chain;
  return read(text, name, base_dir, chain, diagnostics);
}

std::optional<GraphDocument> read_graph_file(const std::filesystem::path& file,
                                             Diagnostics& diagnostics) {
  const auto text = read_text(file);
  if (!text) {
    diagnostics.error(SourceLoc{file.string(), 0, 0}, "unreadable-file", "cannot read graph file");
    return std::nullopt;
  }
  std::vector<fs::path> chain{fs::weakly_canonical(file)};
  return read(*text, file.string(), file.parent_path(), chain, diagnostics);
}

}  // namespace gslift
