#include "param/param_table.hpp"

#include <catch2/catch.hpp>

namespace gslift {
namespace {

enum class Mode { Fast, Exact };
const EnumNames<Mode>& mode_names() {
  static const EnumNames<Mode> names = {{Mode::Fast, "fast"}, {Mode::Exact, "exact"}};
  return names;
}

struct Inner {
  int k = 3;
  double eps = 0.5;
};

struct Options {
  int steps = 10;
  float rate = 0.25f;
  bool verbose = false;
  std::string path;
  Mode mode = Mode::Exact;
  std::vector<double> weights{1.0, 2.0};
  Inner inner;
};

ParamTable<Inner> inner_table() {
  return ParamTable<Inner>()
      .add("k", &Inner::k, "neighbours", 1, 100)
      .add("eps", &Inner::eps, "epsilon", 0, 1);
}

ParamTable<Options> table() {
  return ParamTable<Options>()
      .add("steps", &Options::steps, "iterations", 1, 1000)
      .add("rate", &Options::rate, "learning rate", 0)
      .add("verbose", &Options::verbose, "talk")
      .add("path", &Options::path, "input file")
      .required()
      .add("mode", &Options::mode, mode_names(), "how")
      .add("weights", &Options::weights, "per-term weights", 0)
      .nest(&Options::inner, inner_table());
}

TEST_CASE("param table: specs carry the struct's defaults, ranges and choices in order") {
  Options defaults;
  defaults.steps = 20;
  const auto specs = table().specs(defaults);
  REQUIRE(specs.size() == 8);
  CHECK(specs[0].name == "steps");
  CHECK(specs[0].type == ParamType::Int);
  CHECK(std::get<int64_t>(*specs[0].default_value) == 20);
  CHECK(*specs[0].min == 1);
  CHECK(*specs[0].max == 1000);
  CHECK(specs[1].type == ParamType::Float);
  CHECK(std::get<double>(*specs[1].default_value) == 0.25);  // exact in binary
  CHECK_FALSE(specs[3].default_value.has_value());           // required
  CHECK(specs[4].type == ParamType::String);
  CHECK(specs[4].choices == std::vector<std::string>{"fast", "exact"});
  CHECK(std::get<std::string>(*specs[4].default_value) == "exact");
  CHECK(specs[5].type == ParamType::FloatList);
  CHECK(specs[6].name == "k");
  CHECK(std::get<int64_t>(*specs[6].default_value) == 3);
  CHECK(specs[7].name == "eps");
}

TEST_CASE("param table: read sets every given field, nested ones too, and keeps the rest") {
  const std::map<std::string, ParamValue> values = {
      {"steps", int64_t{7}},
      {"rate", int64_t{2}},  // a YAML integer where a float is declared
      {"mode", std::string("fast")},
      {"path", std::string("a.ply")},
      {"k", int64_t{9}}};
  const Options o = table().read(values);
  CHECK(o.steps == 7);
  CHECK(o.rate == 2.0f);
  CHECK(o.mode == Mode::Fast);
  CHECK(o.path == "a.ply");
  CHECK(o.inner.k == 9);
  CHECK(o.inner.eps == 0.5);  // not given: the start value
  CHECK_FALSE(o.verbose);
}

TEST_CASE("param table: check names every violated field, validate throws with all of them") {
  Options o;
  CHECK(table().check(o).empty());
  o.steps = 0;
  o.inner.eps = 2;
  o.weights = {1, -1};
  const auto problems = table().check(o);
  REQUIRE(problems.size() == 3);
  CHECK(problems[0].rfind("steps: ", 0) == 0);
  CHECK(problems[1].rfind("weights: ", 0) == 0);
  CHECK(problems[2].rfind("eps: ", 0) == 0);
  try {
    table().validate(o, "my options");
    FAIL("validate accepted out-of-range fields");
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    CHECK(what.rfind("my options: steps: ", 0) == 0);
    CHECK(what.find("eps: ") != std::string::npos);
  }
}

TEST_CASE("param table: a string list may name its choices") {
  struct Lists {
    std::vector<std::string> free{"a"};
    std::vector<std::string> picked{"rgb"};
  };
  const auto specs = ParamTable<Lists>()
                         .add("free", &Lists::free, "anything")
                         .add("picked", &Lists::picked, "channels", {"rgb", "depth"})
                         .specs();
  REQUIRE(specs.size() == 2);
  CHECK(specs[0].type == ParamType::StringList);
  CHECK(specs[0].choices.empty());
  CHECK(specs[1].choices == std::vector<std::string>{"rgb", "depth"});
  CHECK(std::get<std::vector<std::string>>(*specs[1].default_value) ==
        std::vector<std::string>{"rgb"});
}

TEST_CASE("enum names: a string that is not a mode is an error naming the accepted ones") {
  CHECK(parse_enum("exact", mode_names(), "mode") == Mode::Exact);
  CHECK(enum_name(Mode::Fast, mode_names()) == "fast");
  try {
    parse_enum("quick", mode_names(), "param 'mode'");
    FAIL("unknown mode accepted");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()) == "param 'mode': 'quick' is not one of {fast, exact}");
  }
  // The rejected text comes from a file: quoted capped, its control characters escaped (issue 33).
  try {
    parse_enum("\x1b[2J" + std::string(1000000, 'q'), mode_names(), "param 'mode'");
    FAIL("unknown mode accepted");
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    CHECK(what.size() < 400);
    CHECK(what.find('\x1b') == std::string::npos);
    CHECK(what.rfind("param 'mode': '\\x1B[2Jqqq", 0) == 0);
    CHECK(what.find("... (1000004 bytes)' is not one of {fast, exact}") != std::string::npos);
  }
}

}  // namespace
}  // namespace gslift
