#include <catch2/catch.hpp>

#include "param/param.hpp"

using namespace gslift;

TEST_CASE("check_param enforces type, range and choices") {
  const ParamSpec sigma = float_param("sigma", 0.5, "doc", 0.0, 1.0);
  CHECK(check_param(sigma, ParamValue{0.7}).empty());
  CHECK(check_param(sigma, ParamValue{1.5}) == "value 1.5 is above the maximum 1.0");
  CHECK(check_param(sigma, ParamValue{-0.5}) == "value -0.5 is below the minimum 0.0");
  CHECK(check_param(sigma, ParamValue{true}) == "expected float, got bool");
  const ParamSpec src = string_param("source", "sam", "doc", {"sam", "grabcut"});
  CHECK(check_param(src, ParamValue{std::string("grabcut")}).empty());
  CHECK(check_param(src, ParamValue{std::string("sum")}) ==
        "value \"sum\" is not one of: sam, grabcut");
  const ParamSpec ks =
      ParamSpec{"ks", ParamType::IntList, ParamValue{std::vector<int64_t>{1}}, 1.0, {}, {}, "doc"};
  CHECK(check_param(ks, ParamValue{std::vector<int64_t>{1, 0}}) ==
        "value 0.0 is below the minimum 1.0");
}

TEST_CASE("param values render as YAML") {
  CHECK(to_string(ParamValue{int64_t{3}}) == "3");
  CHECK(to_string(ParamValue{2.0}) == "2.0");
  CHECK(to_string(ParamValue{std::string("a\"b")}) == "\"a\\\"b\"");
  CHECK(to_string(ParamValue{std::vector<double>{0.5, 1}}) == "[0.5, 1.0]");
}
