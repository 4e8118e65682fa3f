#include "graph/substitute.hpp"

#include <filesystem>
#include <optional>
#include <regex>

#include "base/utf8.hpp"
#include "graph/suggest.hpp"

namespace gslift {

namespace {

const std::regex& var_name_re() {
  static const std::regex re("[A-Za-z_][A-Za-z0-9_]*");
  return re;
}

class Substitution {
 public:
  Substitution(const GraphDocument& doc, const std::map<std::string, std::string>& vars,
               Diagnostics& diagnostics)
      : doc_(doc), vars_(vars), diagnostics_(diagnostics) {}

  // The value with its ${} expanded, in a scalar or in the elements of a list (params hold no
  // deeper values; not descending also keeps recursive aliases harmless). The value itself when
  // there is nothing to expand or on error.
  // The folder a path in `param` is relative to once ${} is expanded: that of the var the value
  // starts with (a path's leading part decides what it is relative to): none for a command-line
  // var, the graph param's file folder for a graph param; otherwise the param's own.
  std::filesystem::path origin(const DocValue& param) const {
    if (!param.value.IsScalar()) return param.dir;
    const std::string& text = param.value.Scalar();
    if (text.compare(0, 2, "${") != 0) return param.dir;
    const size_t close = text.find('}');
    if (close == std::string::npos) return param.dir;
    const std::string name = text.substr(2, close - 2);
    if (vars_.count(name)) return {};
    if (auto p = doc_.params.find(name); p != doc_.params.end()) return p->second.dir;
    return param.dir;
  }

  YAML::Node apply(const YAML::Node& value, const SourceLoc& at) {
    if (!value.IsSequence()) return apply_scalar(value, at);
    YAML::Node out(YAML::NodeType::Sequence);
    for (const auto& e : value) out.push_back(apply_scalar(e, at));
    return out;
  }

 private:
  YAML::Node apply_scalar(const YAML::Node& value, const SourceLoc& at) {
    if (!value.IsScalar() || value.Scalar().find("${") == std::string::npos) return value;
    const std::string& text = value.Scalar();
    if (text.size() > 3 && text.compare(0, 2, "${") == 0 && text.back() == '}') {
      const std::string name = text.substr(2, text.size() - 3);
      if (std::regex_match(name, var_name_re())) {
        if (auto source = lookup(name, at)) return *source;
        return value;
      }
    }
    if (auto expanded = expand(text, at)) {
      YAML::Node out(*expanded);
      out.SetTag("!");  // text with something inserted is a string, like a quoted scalar
      return out;
    }
    return value;
  }

  // The source of ${name}: a var (plain text, typed later like an unquoted YAML scalar) or a
  // graph param's YAML value. Reports `unknown-var` when there is none.
  std::optional<YAML::Node> lookup(const std::string& name, const SourceLoc& at) {
    if (auto v = vars_.find(name); v != vars_.end()) return YAML::Node(v->second);
    if (auto p = doc_.params.find(name); p != doc_.params.end()) {
      // A graph param declared null has no default: the user must give it (production SAGA's
      // prompt file), and is told so before anything runs.
      if (p->second.value.IsNull()) {
        diagnostics_.error(at, "unset-param",
                           "graph param '" + name + "' has no value (declared null at " +
                               p->second.value_loc.str() + ")",
                           "give it with --set " + name + "=VALUE");
        return std::nullopt;
      }
      return p->second.value;
    }
    std::vector<std::string> known;
    for (const auto& [k, v] : vars_) known.push_back(k);
    for (const auto& [k, v] : doc_.params) known.push_back(k);
    diagnostics_.error(at, "unknown-var", "undefined variable '${" + name + "}'",
                       suggest(name, known));
    return std::nullopt;
  }

  std::optional<std::string> expand(const std::string& text, const SourceLoc& at) {
    std::string out;
    size_t i = 0;
    while (i < text.size()) {
      if (text.compare(i, 3, "$${") == 0) {
        out += "${";
        i += 3;
        continue;
      }
      if (text.compare(i, 2, "${") != 0) {
        out += text[i++];
        continue;
      }
      const size_t close = text.find('}', i + 2);
      const std::string name =
          close == std::string::npos ? std::string() : text.substr(i + 2, close - i - 2);
      if (!std::regex_match(name, var_name_re())) {
        diagnostics_.error(at, "bad-substitution", "malformed '${' in \"" + printable(text) + "\"",
                           "write ${name}, or $${ for a literal ${");
        return std::nullopt;
      }
      const auto source = lookup(name, at);
      if (!source) return std::nullopt;
      if (!source->IsScalar()) {
        diagnostics_.error(at, "bad-substitution",
                           "'${" + name + "}' is not a scalar and cannot be inserted into \"" +
                               printable(text) + "\"");
        return std::nullopt;
      }
      out += source->Scalar();
      i = close + 1;
    }
    return out;
  }

  const GraphDocument& doc_;
  const std::map<std::string, std::string>& vars_;
  Diagnostics& diagnostics_;
};

}  // namespace

void substitute_vars(GraphDocument& doc, const std::map<std::string, std::string>& vars,
                     Diagnostics& diagnostics) {
  Substitution substitution(doc, vars, diagnostics);
  for (auto& node : doc.nodes)
    for (auto& [name, param] : node.params) {
      param.dir = substitution.origin(param);
      param.value.reset(substitution.apply(param.value, param.value_loc));
    }
}

}  // namespace gslift
