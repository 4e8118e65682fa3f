#include "cli/node_catalogue.hpp"

#include <algorithm>

namespace gslift {

namespace {

std::string padded(const std::string& s, size_t width) {
  return s + std::string(width > s.size() ? width - s.size() : 0, ' ');
}

// A range bound in the param's own number type: "0" for an int, "0.0" for a float.
std::string bound_text(const ParamSpec& p, double x) {
  const bool integral = p.type == ParamType::Int || p.type == ParamType::IntList;
  return integral ? std::to_string(static_cast<int64_t>(x)) : to_string(ParamValue{x});
}

std::string param_line(const ParamSpec& p) {
  std::string line = p.name + ": " + to_string(p.type);
  line += p.default_value ? " = " + to_string(*p.default_value) : std::string(" (required)");
  if (p.min || p.max)
    line += " in [" + (p.min ? bound_text(p, *p.min) : std::string("-inf")) + ", " +
            (p.max ? bound_text(p, *p.max) : std::string("inf")) + "]";
  if (!p.choices.empty()) {
    std::string all;
    for (const auto& c : p.choices) all += (all.empty() ? "" : ", ") + c;
    line += " one of {" + all + "}";
  }
  return line;
}

std::string ports_text(const char* title, const std::vector<PortSpec>& ports) {
  std::string out = std::string(title) + ":\n";
  if (ports.empty()) return out + "  (none)\n";
  for (const auto& p : ports) {
    std::string with;
    for (const auto& other : p.wired_with) with += (with.empty() ? ", with " : " and ") + other;
    out += "  " + p.name + ": " + p.type + (p.optional ? " (optional" + with + ")" : "") +
           "\n      " + p.doc + "\n";
  }
  return out;
}

}  // namespace

std::string catalogue_text(const Registry& registry) {
  size_t width = 0;
  for (const auto& t : registry.types()) width = std::max(width, t.size());
  std::string out;
  for (const auto& t : registry.types())
    out += padded(t, width) + "  " + registry.find(t)->doc + "\n";
  return out;
}

std::string node_type_text(const NodeSpec& spec, const std::string& source) {
  std::string out = spec.type + ": " + spec.doc + "\n";
  if (!source.empty()) out += "source: " + source + "\n";
  out += ports_text("inputs", spec.inputs);
  out += ports_text("outputs", spec.outputs);
  out += "params:\n";
  if (spec.params.empty()) out += "  (none)\n";
  // The params a user sets first, then the advanced ones under their own heading.
  for (const bool advanced : {false, true}) {
    bool heading = !advanced;
    for (const auto& p : spec.params) {
      if (p.advanced != advanced) continue;
      if (!heading) out += "advanced params:\n";
      heading = true;
      out += "  " + param_line(p) + "\n      " + p.doc + "\n";
      for (const auto& [choice, values] : p.presets) {
        std::string all;
        for (const auto& [name, value] : values)
          all += (all.empty() ? "" : ", ") + name + ": " + to_string(value);
        out += "      " + choice + " sets {" + all + "}\n";
      }
    }
  }
  return out;
}

}  // namespace gslift
