// Typed node parameters: the single declaration (ParamSpec) that drives YAML validation, `--set`
// parsing, `gslift nodes TYPE` and the values a node reads at run time (GStreamer's GParamSpec
// idea).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace gslift {

enum class ParamType { Int, Float, Bool, String, IntList, FloatList, StringList };

// "int", "float", "bool", "string", "list<int>", "list<float>", "list<string>".
const char* to_string(ParamType t);

// A parameter value. Ints are 64-bit; a YAML integer is accepted where a float is declared.
using ParamValue = std::variant<int64_t, double, bool, std::string, std::vector<int64_t>,
                                std::vector<double>, std::vector<std::string>>;

// Other params of the same node and the values one choice of a String param sets them to.
using ParamPreset = std::vector<std::pair<std::string, ParamValue>>;

ParamType type_of(const ParamValue& v);
// Human-readable, YAML-compatible rendering ("0.5", "true", "[1, 2]", "\"text\"").
std::string to_string(const ParamValue& v);

struct ParamSpec {
  std::string name;
  ParamType type = ParamType::Float;
  // Absent default = required parameter (the YAML must set it).
  std::optional<ParamValue> default_value;
  // Inclusive numeric range, checked for Int/Float and element-wise for the list types.
  std::optional<double> min;
  std::optional<double> max;
  // Allowed values for String params (an enum); empty = any string.
  std::vector<std::string> choices;
  std::string doc;
  // A String param naming a file or folder: a relative value written in a graph file is taken
  // relative to that file's folder, like `extends:` (validate.cpp, docs/graph_format.md).
  bool path = false;
  // For a String param with choices: the params a choice sets (a named setting, e.g.
  // splat.reconstruct's `recipe`). The graph resolves them where the graph file leaves those
  // params unset (graph/validate.cpp), so the resolved graph holds the values that run.
  std::map<std::string, ParamPreset> presets{};
  // Listed after the others by `gslift nodes TYPE`: a param few users need to set.
  bool advanced = false;
};

// Builders that keep node registrations short and readable.
ParamSpec int_param(std::string name, int64_t def, std::string doc,
                    std::optional<double> min = std::nullopt,
                    std::optional<double> max = std::nullopt);
ParamSpec float_param(std::string name, double def, std::string doc,
                      std::optional<double> min = std::nullopt,
                      std::optional<double> max = std::nullopt);
ParamSpec bool_param(std::string name, bool def, std::string doc);
ParamSpec string_param(std::string name, std::string def, std::string doc,
                       std::vector<std::string> choices = {});
ParamSpec required_string_param(std::string name, std::string doc);

// Checks a value against its spec (type, range, choices). Returns an empty string when valid,
// otherwise the violated constraint, e.g. "value 1.5 is above the maximum 1".
std::string check_param(const ParamSpec& spec, const ParamValue& value);

}  // namespace gslift
