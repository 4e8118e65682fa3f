// base/json_read.hpp: the nesting cap every JSON read goes through (issue 33: a 100,000-level
// document parsed, then overflowed the stack when dumped or copied).
#include "base/json_read.hpp"

#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;

namespace {

std::string arrays(size_t levels) {
  return std::string(levels, '[') + std::string(levels, ']');
}

}  // namespace

TEST_CASE("json_too_deep_at finds the bracket that opens one level too many", "[json]") {
  CHECK(json_too_deep_at("[[1], {\"a\": [2]}]", 2) == 13);  // the '[' of [2], byte 13
  CHECK(json_too_deep_at("[[1], {\"a\": [2]}]", 3) == 0);
  // Brackets inside strings, escaped quotes included, are text, not nesting.
  CHECK(json_too_deep_at(R"(["[[[[", "\"{{{{", "\\"])", 1) == 0);
  CHECK(json_too_deep_at(R"(["\\", [0]])", 1) == 8);  // the second [, byte 8
  CHECK(json_too_deep_at(arrays(kMaxJsonDepth)) == 0);
  CHECK(json_too_deep_at(arrays(kMaxJsonDepth + 1)) == kMaxJsonDepth + 1);
}

TEST_CASE("parse_json refuses 200,000 levels with the parser's own error, at the byte", "[json]") {
  CHECK(parse_json(arrays(kMaxJsonDepth)).dump().size() == 2 * kMaxJsonDepth);
  CHECK(parse_json(R"({"k": "[[[", "v": [1, 2]})")["v"][1] == 2);
  std::string deep;
  for (int i = 0; i < 200000; ++i) deep += "{\"a\":";
  deep += "1" + std::string(200000, '}');
  CHECK_THROWS_WITH(parse_json(deep), Contains("parse error at byte 1281") &&
                                          Contains("nested more than 256 levels"));
  CHECK_THROWS_AS(parse_json(deep), nlohmann::json::parse_error);
  CHECK(parse_json_or_discarded(deep).is_discarded());
  CHECK(parse_json_or_discarded("[1, ").is_discarded());
  CHECK(parse_json_or_discarded("[1]") == nlohmann::json::array({1}));
}
