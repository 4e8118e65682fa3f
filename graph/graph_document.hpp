// A graph as written: the YAML of a file and of the files it extends merged, --set overrides
// applied, but nothing yet checked against the node catalog. Every value keeps where it was
// written so that validation can point at the right file, line and column.
#pragma once

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "graph/diagnostics.hpp"
#include "graph/graph.hpp"

namespace gslift {

// Where a parsed YAML node starts in `file` (1-based); line 0 for nodes built in code.
SourceLoc loc_of(const YAML::Node& node, const std::string& file);

// One `key: value` entry of a map.
struct DocValue {
  YAML::Node value;
  SourceLoc key_loc;
  SourceLoc value_loc;
  // The folder of the graph file the value was written in, which relative path params are
  // resolved against; empty for the command line (--set, --input) and for text read without a
  // folder, whose paths stay relative to the current directory.
  std::filesystem::path dir;

  DocValue() = default;
  DocValue(YAML::Node v, SourceLoc key, SourceLoc at, std::filesystem::path dir = {});
  DocValue(const DocValue&) = default;
  // yaml-cpp's Node::operator= writes through to the node it refers to (an alias of it, a base
  // file's node); rebinding instead keeps an override from changing any other value.
  DocValue& operator=(const DocValue& other);
};

struct DocNode {
  std::string id;
  SourceLoc loc;     // the key of its latest declaration (a derived file's, when overridden)
  std::string type;  // empty when no file gave one
  SourceLoc type_loc;
  std::map<std::string, DocValue> inputs;  // input port -> "node.port"
  // Inputs kept from a declaration whose type was later replaced: the new type may not have
  // these ports, in which case they are dropped with a warning rather than reported as errors.
  std::set<std::string> inputs_of_replaced_type;
  std::map<std::string, DocValue> params;
  // Keys other than type/in/params: reported by validation, which knows the type and can tell
  // a param or input written outside `params:`/`in:`.
  std::map<std::string, DocValue> unknown_keys;
  // Declared `id: null` (or `~`) in a derived file: the base's node is removed (a production
  // graph drops the evaluated graph's ground-truth branch this way).
  bool removed = false;
};

struct GraphDocument {
  std::string name;
  std::vector<std::string> files;  // base first
  std::map<std::string, DocValue> params;
  std::vector<DocNode> nodes;  // declaration order: base nodes first, then new derived ones

  DocNode* find(const std::string& id);
  std::vector<std::string> node_ids() const;
};

// Applies a later declaration of a node (a derived file's, or a --set) onto it. A `type` that
// differs from the current one replaces the stage: its params restart from `over` (the dropped
// ones are listed in a `dropped-params` warning). Otherwise, and for `in` always, the maps are
// merged key by key, `over` winning.
void merge_node(DocNode& node, const DocNode& over, Diagnostics& diagnostics);

// Applies a derived file onto its base: name and params key by key, nodes by id (merge_node),
// new nodes appended in their order, nodes declared null removed (`nothing-to-remove` when the
// base has no such node).
void merge_document(GraphDocument& base, const GraphDocument& derived, Diagnostics& diagnostics);

}  // namespace gslift
