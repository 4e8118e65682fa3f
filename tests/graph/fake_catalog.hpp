// A small node catalog for the graph tests: typed ports and params of every kind, without the
// real node families.
#pragma once

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "graph/loader.hpp"

namespace gslift::test {

class FakeCatalog : public NodeCatalog {
 public:
  FakeCatalog() {
    add({"src.make",
         "a number",
         {},
         {{"value", "Number", "", false}},
         {float_param("value", 1.0, "the number", -100.0, 100.0)}});
    add({"src.text",
         "a text",
         {},
         {{"text", "String", "", false}},
         {required_string_param("text", "the text")}});
    add({"math.add",
         "a + b, scaled",
         {{"a", "Number", "", false}, {"b", "Number", "", false}},
         {{"sum", "Number", "", false}, {"carry", "Number", "", false}},
         {float_param("scale", 1.0, "factor on the sum", 0.0, 10.0),
          int_param("count", 1, "repetitions", 1.0),
          string_param("mode", "fast", "how", {"fast", "exact"}),
          bool_param("verbose", false, "log more"),
          ParamSpec{"weights",
                    ParamType::FloatList,
                    ParamValue{std::vector<double>{1.0, 1.0}},
                    0.0,
                    std::nullopt,
                    {},
                    "per-input weights"},
          ParamSpec{"ks",
                    ParamType::IntList,
                    ParamValue{std::vector<int64_t>{1}},
                    1.0,
                    std::nullopt,
                    {},
                    "sizes"},
          ParamSpec{"tags",
                    ParamType::StringList,
                    ParamValue{std::vector<std::string>{}},
                    std::nullopt,
                    std::nullopt,
                    {},
                    "labels"}}});
    add({"math.mul",
         "a * b",
         {{"a", "Number", "", false}, {"b", "Number", "", true}},
         {{"product", "Number", "", false}},
         {float_param("factor", 2.0, "extra factor")}});
    add({"sink.number", "prints a number", {{"value", "Number", "", false}}, {}, {}});
    // `offset` means nothing without `scale`: wired alone it is refused (PortSpec::wired_with).
    add({"math.affine",
         "value * scale + offset",
         {{"value", "Number", "", false},
          {"offset", "Number", "", true, {}, {"scale"}},
          {"scale", "Number", "", true}},
         {{"result", "Number", "", false}},
         {}});
    add({"sink.print",
         "prints a text",
         {{"text", "String", "", false}},
         {},
         {string_param("prefix", "", "printed first")}});
  }

  const NodeSpec* find(const std::string& type) const override {
    auto it = specs_.find(type);
    return it == specs_.end() ? nullptr : &it->second;
  }

  std::vector<std::string> types() const override {
    std::vector<std::string> out;
    for (const auto& [type, spec] : specs_) out.push_back(type);
    return out;
  }

  // A test's own node type beside the shared ones.
  void add(NodeSpec spec) { specs_[spec.type] = std::move(spec); }

 private:
  std::map<std::string, NodeSpec> specs_;
};

// The diagnostics of `result` with `code`.
inline std::vector<Diagnostic> with_code(const LoadResult& result, const std::string& code) {
  std::vector<Diagnostic> out;
  for (const auto& d : result.diagnostics)
    if (d.code == code) out.push_back(d);
  return out;
}

// "name:line:col" of the `nth` (1-based) occurrence of `needle` in `text`.
inline std::string position(const std::string& text, const std::string& needle, int nth = 1,
                            const std::string& name = "test.yaml") {
  size_t at = std::string::npos;
  for (int i = 0; i < nth; ++i) at = text.find(needle, at == std::string::npos ? 0 : at + 1);
  REQUIRE(at != std::string::npos);
  const size_t line_start = text.rfind('\n', at);
  const int column = static_cast<int>(at - (line_start == std::string::npos ? 0 : line_start + 1));
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + at, '\n'));
  return name + ":" + std::to_string(line) + ":" + std::to_string(column + 1);
}

// Loads inline YAML (named "test.yaml" in diagnostics) against the fake catalogue.
inline LoadResult load_test_yaml(const std::string& yaml, const LoadOptions& options = {}) {
  static const FakeCatalog catalog;
  return load_graph_text(yaml, "test.yaml", catalog, options);
}

}  // namespace gslift::test
