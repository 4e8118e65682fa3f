// The contract of a node type: typed input/output ports and parameters. The graph validator
// checks YAML against these; the runtime registry pairs each with the function that runs it.
#pragma once

#include <string>
#include <vector>

#include "param/capture_need.hpp"
#include "param/param.hpp"

namespace gslift {

struct PortSpec {
  std::string name;
  // The port's value type by name ("Capture", "BoxSet", "GaussianModel", ...). Two ports connect
  // only when their type names are equal; the runtime maps names to C++ types (runtime/value.hpp).
  std::string type;
  std::string doc;
  bool optional = false;  // inputs only: the node runs without it
  // Capture inputs only: what the node reads from the capture besides its posed views (VLM
  // replies, SAM masks, ground truth, held-out views). Checked before the run
  // (runtime/preflight.hpp); {} so that a port written without it is complete.
  std::vector<CaptureNeed> needs{};
  // Optional inputs only: the other inputs this one means nothing without (filter_3d's prompts
  // and the capture their masks were drawn in). Validation refuses the port wired alone.
  std::vector<std::string> wired_with{};
};

struct NodeSpec {
  std::string type;  // registry key, lowercase dotted: "boxes.cluster"
  std::string doc;   // one line
  std::vector<PortSpec> inputs;
  std::vector<PortSpec> outputs;
  // Filled from the node's ParamTable when it is registered; {} so that a spec written without
  // it is complete (-Wmissing-field-initializers).
  std::vector<ParamSpec> params{};
  // False for a node whose results depend on more than its params, inputs and files (a network
  // service): the stage cache never stands in for it.
  bool cacheable = true;

  const PortSpec* find_input(const std::string& name) const;
  const PortSpec* find_output(const std::string& name) const;
  const ParamSpec* find_param(const std::string& name) const;
};

// What the graph layer needs to know about node types: looked up by name, listed for suggestions.
class NodeCatalog {
 public:
  virtual ~NodeCatalog() = default;
  virtual const NodeSpec* find(const std::string& type) const = 0;
  virtual std::vector<std::string> types() const = 0;
};

}  // namespace gslift
