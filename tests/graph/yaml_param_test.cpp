#include <catch2/catch.hpp>

#include "graph/yaml_param.hpp"

using namespace gslift;

namespace {

// The value of `key` in a one-entry YAML map, so that quoting is as in a graph file.
YAML::Node value(const std::string& yaml) {
  return YAML::Load("v: " + yaml)["v"];
}

std::string error_of(const std::string& yaml, ParamType type) {
  std::string error;
  CHECK_FALSE(param_from_yaml(value(yaml), type, error));
  return error;
}

template <class T>
T as(const std::string& yaml, ParamType type) {
  std::string error;
  const auto v = param_from_yaml(value(yaml), type, error);
  INFO(error);
  REQUIRE(v);
  return std::get<T>(*v);
}

}  // namespace

TEST_CASE("plain scalars are typed by the YAML core schema") {
  CHECK(yaml_kind(value("12")) == "int");
  CHECK(yaml_kind(value("-3")) == "int");
  CHECK(yaml_kind(value("0.5")) == "float");
  CHECK(yaml_kind(value("1e-3")) == "float");
  CHECK(yaml_kind(value(".5")) == "float");
  CHECK(yaml_kind(value("True")) == "bool");
  CHECK(yaml_kind(value("yes")) == "string");
  CHECK(yaml_kind(value("\"12\"")) == "string");
  CHECK(yaml_kind(value("[1, 2]")) == "list<int>");
  CHECK(yaml_kind(value("[1, 2.5]")) == "list<float>");
  CHECK(yaml_kind(value("[1, a]")) == "list<string>");
  CHECK(yaml_kind(value("[[1]]")) == "list");
  CHECK(yaml_kind(value("{a: 1}")) == "map");
  CHECK(yaml_kind(value("~")) == "null");
}

TEST_CASE("values convert to the declared type") {
  CHECK(as<int64_t>("-42", ParamType::Int) == -42);
  CHECK(as<double>("3", ParamType::Float) == 3.0);  // int accepted where float is declared
  CHECK(as<double>("2.5e2", ParamType::Float) == 250.0);
  CHECK(as<bool>("FALSE", ParamType::Bool) == false);
  CHECK(as<std::string>("12", ParamType::String) == "12");  // plain text is a string's text
  CHECK(as<std::string>("'a b'", ParamType::String) == "a b");
  CHECK(as<std::vector<int64_t>>("[3, -1]", ParamType::IntList) == std::vector<int64_t>{3, -1});
  CHECK(as<std::vector<double>>("[1, 0.5]", ParamType::FloatList) == std::vector<double>{1.0, 0.5});
  CHECK(as<std::vector<std::string>>("[a, 2]", ParamType::StringList) ==
        std::vector<std::string>{"a", "2"});
  CHECK(as<std::vector<double>>("[]", ParamType::FloatList).empty());
}

TEST_CASE("wrong kinds are rejected with expected/got") {
  CHECK(error_of("1.5", ParamType::Int) == "expected int, got float");
  CHECK(error_of("\"1\"", ParamType::Int) == "expected int, got string");
  CHECK(error_of("\"0.5\"", ParamType::Float) == "expected float, got string");
  CHECK(error_of("1", ParamType::Bool) == "expected bool, got int");
  CHECK(error_of("[1]", ParamType::String) == "expected string, got list<int>");
  CHECK(error_of("[1, 1.5]", ParamType::IntList) == "expected list<int>, got list<float>");
  CHECK(error_of("[[1]]", ParamType::StringList) == "expected list<string>, got list");
  CHECK(error_of("~", ParamType::Float) == "expected float, got null");
  CHECK(error_of("99999999999999999999", ParamType::Int) ==
        "number 99999999999999999999 is out of range");
  CHECK(error_of("1e999", ParamType::Float) == "number 1e999 is out of range");
  CHECK(error_of("[1, 1e999]", ParamType::FloatList) == "number 1e999 is out of range");
  CHECK(error_of("[1, 99999999999999999999]", ParamType::IntList) ==
        "number 99999999999999999999 is out of range");
}

TEST_CASE("graph params infer their type") {
  std::string error;
  CHECK(std::get<int64_t>(*infer_param(value("3"), error)) == 3);
  CHECK(std::get<std::vector<double>>(*infer_param(value("[1, 2.5]"), error)) ==
        std::vector<double>{1.0, 2.5});
  CHECK(std::get<std::vector<std::string>>(*infer_param(value("[]"), error)).empty());
  CHECK_FALSE(infer_param(value("{a: 1}"), error));
  CHECK(error == "expected a scalar or a list of scalars, got map");
}
