// One declaration per parameter. A ParamTable<Options> lists the fields of an options struct once
// (name, member, doc, range or choices) and generates from that list everything that used to be
// written by hand next to it: the node's ParamSpecs (with the struct's defaults), the reading of a
// node's validated params into the struct, and check(), which any C++ caller (a bench, a test)
// can run on a struct it filled itself. Mode params are C++ enums with one name table
// (EnumNames), so a string that is not a mode is an error, never a silent default.
//
// The table holds getters and setters rather than raw member pointers so that a nested options
// struct (e.g. the HDBSCAN params inside the lifting params) contributes its fields by `nest`.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "base/utf8.hpp"
#include "param/param.hpp"

namespace gslift {

// The names of an enum's values, in the order they are listed to users.
template <class E>
using EnumNames = std::vector<std::pair<E, std::string>>;

template <class E>
const std::string& enum_name(E value, const EnumNames<E>& names) {
  for (const auto& [v, name] : names)
    if (v == value) return name;
  throw std::logic_error("enum value without a name");
}

template <class E>
std::vector<std::string> enum_choices(const EnumNames<E>& names) {
  std::vector<std::string> out;
  for (const auto& entry : names) out.push_back(entry.second);
  return out;
}

// Throws std::invalid_argument naming `what` and every accepted name; the rejected text is quoted
// capped and escaped (it comes from a file or the command line).
template <class E>
E parse_enum(const std::string& text, const EnumNames<E>& names, const std::string& what) {
  for (const auto& [v, name] : names)
    if (name == text) return v;
  std::string all;
  for (const auto& entry : names) all += (all.empty() ? "" : ", ") + entry.second;
  throw std::invalid_argument(what + ": '" + printable(text) + "' is not one of {" + all + "}");
}

template <class O>
class ParamTable {
 public:
  struct Field {
    ParamSpec spec;  // without its default: that comes from the options struct
    bool required = false;
    std::function<ParamValue(const O&)> get;
    std::function<void(O&, const ParamValue&)> set;
  };

  // An integer field (int, int64_t, ...).
  template <class T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool>, int> = 0>
  ParamTable& add(std::string name, T O::*m, std::string doc, std::optional<double> min = {},
                  std::optional<double> max = {}) {
    return push(
        spec(std::move(name), ParamType::Int, std::move(doc), min, max),
        [m](const O& o) { return ParamValue{static_cast<int64_t>(o.*m)}; },
        [m](O& o, const ParamValue& v) { o.*m = static_cast<T>(std::get<int64_t>(v)); });
  }
  // A real field (double or float).
  template <class T, std::enable_if_t<std::is_floating_point_v<T>, int> = 0>
  ParamTable& add(std::string name, T O::*m, std::string doc, std::optional<double> min = {},
                  std::optional<double> max = {}) {
    return push(
        spec(std::move(name), ParamType::Float, std::move(doc), min, max),
        [m](const O& o) { return ParamValue{static_cast<double>(o.*m)}; },
        [m](O& o, const ParamValue& v) { o.*m = static_cast<T>(real(v)); });
  }
  ParamTable& add(std::string name, bool O::*m, std::string doc) {
    return push(
        spec(std::move(name), ParamType::Bool, std::move(doc)),
        [m](const O& o) { return ParamValue{o.*m}; },
        [m](O& o, const ParamValue& v) { o.*m = std::get<bool>(v); });
  }
  // A free string, or one of `choices` when they are given. A mode belongs in an enum field.
  ParamTable& add(std::string name, std::string O::*m, std::string doc,
                  std::vector<std::string> choices = {}) {
    ParamSpec s = spec(std::move(name), ParamType::String, std::move(doc));
    s.choices = std::move(choices);
    return push(
        std::move(s), [m](const O& o) { return ParamValue{o.*m}; },
        [m](O& o, const ParamValue& v) { o.*m = std::get<std::string>(v); });
  }
  // A mode: a string param whose choices are the enum's names.
  template <class E, std::enable_if_t<std::is_enum_v<E>, int> = 0>
  ParamTable& add(std::string name, E O::*m, const EnumNames<E>& names, std::string doc) {
    ParamSpec s = spec(name, ParamType::String, std::move(doc));
    s.choices = enum_choices(names);
    return push(
        std::move(s), [m, names](const O& o) { return ParamValue{enum_name(o.*m, names)}; },
        [m, names, name](O& o, const ParamValue& v) {
          o.*m = parse_enum(std::get<std::string>(v), names, "param '" + name + "'");
        });
  }
  ParamTable& add(std::string name, std::vector<double> O::*m, std::string doc,
                  std::optional<double> min = {}, std::optional<double> max = {}) {
    return push(
        spec(std::move(name), ParamType::FloatList, std::move(doc), min, max),
        [m](const O& o) { return ParamValue{o.*m}; },
        [m](O& o, const ParamValue& v) { o.*m = std::get<std::vector<double>>(v); });
  }
  // A list of free strings, or of `choices` when they are given.
  ParamTable& add(std::string name, std::vector<std::string> O::*m, std::string doc,
                  std::vector<std::string> choices = {}) {
    ParamSpec s = spec(std::move(name), ParamType::StringList, std::move(doc));
    s.choices = std::move(choices);
    return push(
        std::move(s), [m](const O& o) { return ParamValue{o.*m}; },
        [m](O& o, const ParamValue& v) { o.*m = std::get<std::vector<std::string>>(v); });
  }
  template <class T, std::enable_if_t<std::is_integral_v<T>, int> = 0>
  ParamTable& add(std::string name, std::vector<T> O::*m, std::string doc,
                  std::optional<double> min = {}, std::optional<double> max = {}) {
    return push(
        spec(std::move(name), ParamType::IntList, std::move(doc), min, max),
        [m](const O& o) { return ParamValue{std::vector<int64_t>((o.*m).begin(), (o.*m).end())}; },
        [m](O& o, const ParamValue& v) {
          const auto& in = std::get<std::vector<int64_t>>(v);
          o.*m = std::vector<T>(in.begin(), in.end());
        });
  }

  // The last added field has no default: a graph must set it.
  ParamTable& required() {
    fields_.back().required = true;
    return *this;
  }
  // The last added field is a mode whose choices set other params of the node (ParamSpec::presets;
  // the registry checks them): `presets` maps a choice to the params it sets and their values.
  ParamTable& presets(std::map<std::string, ParamPreset> presets) {
    fields_.back().spec.presets = std::move(presets);
    return *this;
  }
  // Every field added after this call (directly or by nest) is advanced (ParamSpec::advanced):
  // the table lists the few params a user sets first, then calls this, then the rest.
  ParamTable& advanced() {
    advanced_ = true;
    return *this;
  }

  // The last added field is a file or folder (ParamSpec::path); it must be a string field.
  ParamTable& path() {
    if (fields_.back().spec.type != ParamType::String)
      throw std::logic_error("param '" + fields_.back().spec.name + "': only a string is a path");
    fields_.back().spec.path = true;
    return *this;
  }

  // Every field of `sub`, reading and writing the member `m`; `doc_suffix` is appended to each
  // field's doc (what the node adds to the meaning, e.g. how a preset interacts).
  template <class S>
  ParamTable& nest(S O::*m, const ParamTable<S>& sub, const std::string& doc_suffix = {}) {
    for (const auto& f : sub.fields()) {
      Field field{f.spec, f.required, nullptr, nullptr};
      field.spec.doc += doc_suffix;
      field.spec.advanced = field.spec.advanced || advanced_;
      field.get = [m, get = f.get](const O& o) { return get(o.*m); };
      field.set = [m, set = f.set](O& o, const ParamValue& v) { set(o.*m, v); };
      fields_.push_back(std::move(field));
    }
    return *this;
  }

  // The fields of `sub` named in `names`, in that order, each renamed prefix + name: a node that
  // trains through another's options exposes a few of its params under its own names.
  template <class S>
  ParamTable& nest(S O::*m, const ParamTable<S>& sub, const std::vector<std::string>& names,
                   const std::string& prefix, const std::string& doc_suffix) {
    ParamTable<S> some;
    for (const auto& name : names) {
      auto f = sub.field(name);
      f.spec.name = prefix + name;
      some.fields_.push_back(std::move(f));
    }
    return nest(m, some, doc_suffix);
  }

  const std::vector<Field>& fields() const { return fields_; }
  // The field of that name; throws std::logic_error when there is none.
  const Field& field(const std::string& name) const {
    for (const auto& f : fields_)
      if (f.spec.name == name) return f;
    throw std::logic_error("no param '" + name + "'");
  }
  // Sets the named field of `o` after checking `value` against its spec; false when the table has
  // no such field. Throws std::invalid_argument naming the param on a bad value.
  bool set(O& o, const std::string& name, const ParamValue& value) const {
    for (const auto& f : fields_) {
      if (f.spec.name != name) continue;
      if (const std::string bad = check_param(f.spec, value); !bad.empty())
        throw std::invalid_argument("param '" + name + "': " + bad);
      f.set(o, value);
      return true;
    }
    return false;
  }

  // The node's params, in table order, with `defaults`' values as their defaults.
  std::vector<ParamSpec> specs(const O& defaults = O{}) const {
    std::vector<ParamSpec> out;
    for (const auto& f : fields_) {
      ParamSpec s = f.spec;
      if (!f.required) s.default_value = f.get(defaults);
      out.push_back(std::move(s));
    }
    return out;
  }

  // `start` with every field found in `values` (a node's validated params) set from it.
  O read(const std::map<std::string, ParamValue>& values, O start = O{}) const {
    for (const auto& f : fields_) {
      auto it = values.find(f.spec.name);
      if (it != values.end()) f.set(start, it->second);
    }
    return start;
  }

  // One message per field whose value breaks its range or choices, "name: what is wrong".
  std::vector<std::string> check(const O& o) const {
    std::vector<std::string> problems;
    for (const auto& f : fields_) {
      const std::string bad = check_param(f.spec, f.get(o));
      if (!bad.empty()) problems.push_back(f.spec.name + ": " + bad);
    }
    return problems;
  }
  // check() for C++ callers: throws std::invalid_argument listing every problem.
  void validate(const O& o, const std::string& what) const {
    const auto problems = check(o);
    if (problems.empty()) return;
    std::string all;
    for (const auto& p : problems) all += (all.empty() ? "" : "; ") + p;
    throw std::invalid_argument(what + ": " + all);
  }

 private:
  static ParamSpec spec(std::string name, ParamType type, std::string doc,
                        std::optional<double> min = {}, std::optional<double> max = {}) {
    ParamSpec s;
    s.name = std::move(name);
    s.type = type;
    s.doc = std::move(doc);
    s.min = min;
    s.max = max;
    return s;
  }
  // A YAML integer is accepted where a float is declared.
  static double real(const ParamValue& v) {
    if (const auto* i = std::get_if<int64_t>(&v)) return static_cast<double>(*i);
    return std::get<double>(v);
  }
  ParamTable& push(ParamSpec s, std::function<ParamValue(const O&)> get,
                   std::function<void(O&, const ParamValue&)> set) {
    s.advanced = advanced_;
    fields_.push_back(Field{std::move(s), false, std::move(get), std::move(set)});
    return *this;
  }

  template <class>
  friend class ParamTable;
  std::vector<Field> fields_;
  bool advanced_ = false;
};

}  // namespace gslift
