#include <catch2/catch.hpp>

#include "graph/suggest.hpp"

using namespace gslift;

TEST_CASE("edit_distance is Levenshtein's") {
  CHECK(edit_distance("kitten", "sitting") == 3);
  CHECK(edit_distance("", "abc") == 3);
  CHECK(edit_distance("abc", "") == 3);
  CHECK(edit_distance("lifting.cvp", "lifting.cvp") == 0);
  CHECK(edit_distance("parmas", "params") == 2);  // a transposition costs two
}

TEST_CASE("nearest_name accepts plausible typos only, earlier candidate on ties") {
  const std::vector<std::string> types{"boxes.cluster", "boxes.to_masks", "lifting.cvp"};
  CHECK(nearest_name("boxes.clster", types) == "boxes.cluster");
  CHECK(nearest_name("lifting.cpv", types) == "lifting.cvp");
  CHECK(nearest_name("splat.reconstruct", types).empty());
  CHECK(nearest_name("ab", {"ax", "ay"}) == "ax");
  // 13 letters allow 4 edits (o, e, s, r -> x), not 5.
  CHECK(nearest_name("bxxxx.cluster", types) == "boxes.cluster");
  CHECK(nearest_name("bxxxx.clustxx", types).empty());
}

TEST_CASE("suggest phrases the hint") {
  CHECK(suggest("valeu", {"value"}) == "did you mean 'value'?");
  CHECK(suggest("zzzzzz", {"value", "sum"}).empty());
  CHECK(suggest("zzzzzz", {"value", "sum"}, true) == "expected one of: value, sum");
  CHECK(suggest("zzzzzz", {}, true).empty());
}
