// The sweep's plan from its command line (runtime/sweep.hpp): --grid values as --set takes them,
// and the grids that cannot be a sweep refused before anything is planned (issue 33).
#include "runtime/sweep.hpp"

#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;
using Values = std::vector<std::string>;

// The name does not start with "--": ctest passes it to Catch, which would read an option.
TEST_CASE("a --grid value splits at commas outside the quotes and brackets that close", "[sweep]") {
  CHECK(parse_grid("lift.x=[1,2],[3,4]").values == Values{"[1,2]", "[3,4]"});
  CHECK(parse_grid("n.s='a,b',c").values == Values{"'a,b'", "c"});
  // A quote or bracket that never closes is a character of its value, as in --set.
  CHECK(parse_grid("capture.path=a'b").values == Values{"a'b"});
  CHECK(parse_grid("n.p=a'b,c\"d,[e,f]g]").values == Values{"a'b", "c\"d", "[e,f]g]"});
  CHECK(parse_grid("n.p=x[1,2").values == Values{"x[1", "2"});
  CHECK(parse_grid("n.p=[a,'b]").values == Values{"[a,'b]"});
  CHECK(parse_grid("n.p=],x").values == Values{"]", "x"});
  CHECK_THROWS_WITH(parse_grid("n.p=a,,b"), Contains("an empty value"));
  CHECK_THROWS_WITH(parse_grid("n.p=1,1"), Contains("value '1' is listed twice"));
}

TEST_CASE("a param on two --grid axes and a grid over the run limit are refused", "[sweep]") {
  const GridAxis a{"a.value", {"1", "2"}}, b{"b.value", {"3"}};
  CHECK(sweep_points({a, b}, {0, 1}).size() == 4);
  CHECK_THROWS_WITH(sweep_points({a, b, GridAxis{"a.value", {"5"}}}, {0}),
                    Contains("--grid a.value is given twice"));
  // 10^6 grid points: refused before planning (they took 5.5 GB, then exit 70).
  GridAxis thousand{"c.value", {}};
  for (int i = 0; i < 1000; ++i) thousand.values.push_back(std::to_string(i));
  GridAxis other = thousand;
  other.param = "d.value";
  CHECK_THROWS_WITH(sweep_points({thousand, other}, {0}), Contains("more than 10000 runs"));
  // Saturating: four such axes would overflow a 64-bit product.
  std::vector<GridAxis> axes;
  for (const char* p : {"e.v", "f.v", "g.v", "h.v", "i.v", "j.v", "k.v"}) {
    axes.push_back(thousand);
    axes.back().param = p;
  }
  CHECK_THROWS_WITH(sweep_points(axes, {0}), Contains("more than 10000 runs"));
  CHECK(sweep_points({thousand}, std::vector<uint64_t>(10, 0)).size() == 10000);
}
