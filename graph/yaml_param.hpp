// Typing YAML values as node parameters. yaml-cpp 0.7 keeps every scalar as text, so the YAML
// core-schema rules are applied here: a quoted scalar is a string; a plain scalar is an int
// ("12", "-3"), a float ("0.5", "1e-3"), a bool (true/false, any case) or else a string.
#pragma once

#include <optional>
#include <string>

#include <yaml-cpp/yaml.h>

#include "param/param.hpp"

namespace gslift {

// What a YAML value holds, in ParamType words ("int", "float", "list<int>", ...), or "map",
// "null", "list" (nested or mixed lists), for messages such as "expected float, got string".
std::string yaml_kind(const YAML::Node& node);

// The value as a parameter of the declared type. A plain scalar is accepted where a string is
// declared (its text), an int where a float is declared (converted); anything else of the wrong
// kind returns nullopt and sets `error` to "expected <type>, got <kind>".
std::optional<ParamValue> param_from_yaml(const YAML::Node& node, ParamType type,
                                          std::string& error);

// The value with its type taken from the YAML itself (graph-level params, which have no
// declaration): lists of ints are list<int>, of ints and floats list<float>, of other scalars
// list<string>; an empty list is list<string>. Maps and nulls return nullopt and set `error`.
std::optional<ParamValue> infer_param(const YAML::Node& node, std::string& error);

}  // namespace gslift
