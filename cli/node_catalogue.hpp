// `gslift nodes`: the node catalogue, generated from the registry's specs (never written by hand).
#pragma once

#include <string>

#include "runtime/registry.hpp"

namespace gslift {

// One line per registered type, sorted: "<type padded>  <doc>".
std::string catalogue_text(const Registry& registry);

// One type in full: doc, the file that registers it (when given, so that a reader goes from the
// catalogue to the code in one hop), inputs and outputs (name, type, optional, doc), and params
// (name, type, default or "required", range, choices, doc).
std::string node_type_text(const NodeSpec& spec, const std::string& source = {});

}  // namespace gslift
