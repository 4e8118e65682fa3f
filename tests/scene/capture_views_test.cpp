// Capture::views_named: the one place that turns a node's `views` param into view indices.
#include <stdexcept>

#include <catch2/catch.hpp>

#include "nodes/scene/capture.hpp"

using namespace gslift;

namespace {

// Five views, the 2nd and 5th held out.
Capture five_views() {
  Capture c;
  for (int i = 0; i < 5; ++i) {
    View v;
    v.name = "cam_" + std::to_string(i);
    v.held_out = i == 1 || i == 4;
    c.views.push_back(v);
  }
  return c;
}

}  // namespace

TEST_CASE("views_named: train, test and all in capture order") {
  const Capture c = five_views();
  CHECK(c.views_named(ViewSet::Train) == std::vector<int>{0, 2, 3});
  CHECK(c.views_named(ViewSet::Test) == std::vector<int>{1, 4});
  CHECK(c.views_named(ViewSet::All) == std::vector<int>{0, 1, 2, 3, 4});
}

TEST_CASE("views_named: a name that is no view set is an error, not every view") {
  CHECK(enum_choices(view_set_names()) == std::vector<std::string>{"train", "test", "all"});
  CHECK(parse_enum("test", view_set_names(), "views") == ViewSet::Test);
  CHECK_THROWS_AS(parse_enum("held_out", view_set_names(), "views"), std::invalid_argument);
}
