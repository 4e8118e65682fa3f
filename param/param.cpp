#include "param/param.hpp"

#include <cmath>
#include <iomanip>
#include <locale>
#include <sstream>

#include "base/utf8.hpp"

namespace gslift {

const char* to_string(ParamType t) {
  switch (t) {
    case ParamType::Int:
      return "int";
    case ParamType::Float:
      return "float";
    case ParamType::Bool:
      return "bool";
    case ParamType::String:
      return "string";
    case ParamType::IntList:
      return "list<int>";
    case ParamType::FloatList:
      return "list<float>";
    case ParamType::StringList:
      return "list<string>";
  }
  return "?";
}

ParamType type_of(const ParamValue& v) {
  return static_cast<ParamType>(v.index());
}

namespace {

// Locale-independent number formatting, shortest form that round-trips for typical values.
std::string number(double x) {
  std::ostringstream os;
  os.imbue(std::locale::classic());
  os << std::setprecision(15) << x;
  std::string s = os.str();
  if (std::isfinite(x) && s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

template <class T, class F>
std::string list(const std::vector<T>& v, F fmt) {
  std::string out = "[";
  for (size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + fmt(v[i]);
  return out + "]";
}

}  // namespace

std::string to_string(const ParamValue& v) {
  switch (type_of(v)) {
    case ParamType::Int:
      return std::to_string(std::get<int64_t>(v));
    case ParamType::Float:
      return number(std::get<double>(v));
    case ParamType::Bool:
      return std::get<bool>(v) ? "true" : "false";
    case ParamType::String:
      return quoted(std::get<std::string>(v));
    case ParamType::IntList:
      return list(std::get<std::vector<int64_t>>(v), [](int64_t x) { return std::to_string(x); });
    case ParamType::FloatList:
      return list(std::get<std::vector<double>>(v), number);
    case ParamType::StringList:
      return list(std::get<std::vector<std::string>>(v), quoted);
  }
  return "?";
}

ParamSpec int_param(std::string name, int64_t def, std::string doc, std::optional<double> min,
                    std::optional<double> max) {
  return ParamSpec{std::move(name), ParamType::Int, ParamValue{def}, min, max, {}, std::move(doc)};
}

ParamSpec float_param(std::string name, double def, std::string doc, std::optional<double> min,
                      std::optional<double> max) {
  return ParamSpec{std::move(name), ParamType::Float, ParamValue{def}, min, max, {},
                   std::move(doc)};
}

ParamSpec bool_param(std::string name, bool def, std::string doc) {
  return ParamSpec{std::move(name), ParamType::Bool, ParamValue{def}, {}, {}, {}, std::move(doc)};
}

ParamSpec string_param(std::string name, std::string def, std::string doc,
                       std::vector<std::string> choices) {
  return ParamSpec{std::move(name),    ParamType::String, ParamValue{std::move(def)}, {}, {},
                   std::move(choices), std::move(doc)};
}

ParamSpec required_string_param(std::string name, std::string doc) {
  return ParamSpec{std::move(name), ParamType::String, std::nullopt, {}, {}, {}, std::move(doc)};
}

namespace {

std::string check_range(const ParamSpec& s, double x) {
  if (!std::isfinite(x)) return "value " + number(x) + " is not finite";
  if (s.min && x < *s.min) return "value " + number(x) + " is below the minimum " + number(*s.min);
  if (s.max && x > *s.max) return "value " + number(x) + " is above the maximum " + number(*s.max);
  return {};
}

}  // namespace

std::string check_param(const ParamSpec& spec, const ParamValue& value) {
  if (type_of(value) != spec.type)
    return std::string("expected ") + to_string(spec.type) + ", got " + to_string(type_of(value));
  switch (spec.type) {
    case ParamType::Int:
      return check_range(spec, static_cast<double>(std::get<int64_t>(value)));
    case ParamType::Float:
      return check_range(spec, std::get<double>(value));
    case ParamType::IntList:
      for (int64_t x : std::get<std::vector<int64_t>>(value))
        if (auto e = check_range(spec, static_cast<double>(x)); !e.empty()) return e;
      return {};
    case ParamType::FloatList:
      for (double x : std::get<std::vector<double>>(value))
        if (auto e = check_range(spec, x); !e.empty()) return e;
      return {};
    case ParamType::String: {
      if (spec.choices.empty()) return {};
      const auto& s = std::get<std::string>(value);
      for (const auto& c : spec.choices)
        if (c == s) return {};
      std::string all;
      for (const auto& c : spec.choices) all += (all.empty() ? "" : ", ") + c;
      return "value \"" + printable(s) + "\" is not one of: " + all;
    }
    default:
      return {};
  }
}

}  // namespace gslift
