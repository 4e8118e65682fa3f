#include "graph/yaml_param.hpp"

#include <locale>
#include <regex>
#include <sstream>

#include "base/utf8.hpp"

namespace gslift {

namespace {

bool is_quoted(const YAML::Node& n) {
  // yaml-cpp tags quoted scalars "!" and plain ones "?"; "!!str" is the explicit string tag.
  return n.Tag() == "!" || n.Tag() == "tag:yaml.org,2002:str";
}

// The ParamType a single scalar holds under the YAML core schema.
ParamType scalar_type(const YAML::Node& n) {
  static const std::regex int_re("[-+]?[0-9]+");
  static const std::regex float_re("[-+]?(\\.[0-9]+|[0-9]+(\\.[0-9]*)?)([eE][-+]?[0-9]+)?");
  static const std::regex bool_re("true|True|TRUE|false|False|FALSE");
  if (is_quoted(n)) return ParamType::String;
  const std::string& s = n.Scalar();
  if (std::regex_match(s, int_re)) return ParamType::Int;
  if (std::regex_match(s, float_re)) return ParamType::Float;
  if (std::regex_match(s, bool_re)) return ParamType::Bool;
  return ParamType::String;
}

// The number in `s`, which scalar_type found to be an int (or a float); nullopt and `error`
// when it does not fit the C++ type.
template <class T>
std::optional<T> parse_number(const std::string& s, std::string& error) {
  std::istringstream is(s);
  is.imbue(std::locale::classic());
  T x{};
  if (is >> x && is.peek() == std::char_traits<char>::eof()) return x;
  error = "number " + printable(s) + " is out of range";
  return std::nullopt;
}

// The list type a sequence of scalars holds; nullopt for nested lists.
std::optional<ParamType> list_type(const YAML::Node& seq) {
  bool all_int = true, all_number = true;
  for (const auto& e : seq) {
    if (!e.IsScalar()) return std::nullopt;
    const ParamType t = scalar_type(e);
    all_int = all_int && t == ParamType::Int;
    all_number = all_number && (t == ParamType::Int || t == ParamType::Float);
  }
  if (seq.size() == 0) return ParamType::StringList;
  if (all_int) return ParamType::IntList;
  if (all_number) return ParamType::FloatList;
  return ParamType::StringList;
}

std::optional<ParamValue> fail(std::string& error, ParamType expected, const YAML::Node& node) {
  error = std::string("expected ") + to_string(expected) + ", got " + yaml_kind(node);
  return std::nullopt;
}

}  // namespace

std::string yaml_kind(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "null";
  if (node.IsMap()) return "map";
  if (node.IsScalar()) return to_string(scalar_type(node));
  if (auto t = list_type(node)) return to_string(*t);
  return "list";
}

std::optional<ParamValue> param_from_yaml(const YAML::Node& node, ParamType type,
                                          std::string& error) {
  const bool scalar = node.IsDefined() && node.IsScalar();
  const bool sequence = node.IsDefined() && node.IsSequence();
  const ParamType held = scalar ? scalar_type(node) : ParamType::String;
  switch (type) {
    case ParamType::Int: {
      if (!scalar || held != ParamType::Int) return fail(error, type, node);
      const auto v = parse_number<int64_t>(node.Scalar(), error);
      return v ? std::optional<ParamValue>(*v) : std::nullopt;
    }
    case ParamType::Float: {
      if (!scalar || (held != ParamType::Int && held != ParamType::Float))
        return fail(error, type, node);
      const auto v = parse_number<double>(node.Scalar(), error);
      return v ? std::optional<ParamValue>(*v) : std::nullopt;
    }
    case ParamType::Bool:
      if (!scalar || held != ParamType::Bool) return fail(error, type, node);
      return ParamValue{node.Scalar().front() == 't' || node.Scalar().front() == 'T'};
    case ParamType::String:
      if (!scalar) return fail(error, type, node);
      return ParamValue{node.Scalar()};
    case ParamType::IntList: {
      if (!sequence || (node.size() > 0 && list_type(node) != ParamType::IntList))
        return fail(error, type, node);
      std::vector<int64_t> v;
      for (const auto& e : node) {
        const auto x = parse_number<int64_t>(e.Scalar(), error);
        if (!x) return std::nullopt;
        v.push_back(*x);
      }
      return ParamValue{v};
    }
    case ParamType::FloatList: {
      const auto held_list = sequence ? list_type(node) : std::nullopt;
      if (!sequence ||
          (node.size() > 0 && held_list != ParamType::IntList && held_list != ParamType::FloatList))
        return fail(error, type, node);
      std::vector<double> v;
      for (const auto& e : node) {
        const auto x = parse_number<double>(e.Scalar(), error);
        if (!x) return std::nullopt;
        v.push_back(*x);
      }
      return ParamValue{v};
    }
    case ParamType::StringList: {
      if (!sequence || !list_type(node)) return fail(error, type, node);
      std::vector<std::string> v;
      for (const auto& e : node) v.push_back(e.Scalar());
      return ParamValue{v};
    }
  }
  return fail(error, type, node);
}

std::optional<ParamValue> infer_param(const YAML::Node& node, std::string& error) {
  std::optional<ParamType> type;
  if (node.IsDefined() && node.IsScalar()) type = scalar_type(node);
  if (node.IsDefined() && node.IsSequence()) type = list_type(node);
  if (!type) {
    error = "expected a scalar or a list of scalars, got " + yaml_kind(node);
    return std::nullopt;
  }
  return param_from_yaml(node, *type, error);
}

}  // namespace gslift
