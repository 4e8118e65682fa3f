// Instance semantics (LangOR §1.3) with hand-picked unit embeddings: every expected label and
// vector below follows from dot products of these.
#include "nodes/association/instance_semantics.hpp"

#include "tests/association/fixed_text_encoder.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using test::vec3;

namespace {

test::FixedTextEncoder table_chair_encoder() {
  return test::FixedTextEncoder({{"table", vec3(1, 0, 0)},
                                 {"chair", vec3(0, 1, 0)},
                                 {"operating table", vec3(0.8f, 0.6f, 0)}});
}

}  // namespace

TEST_CASE("three or more masks: the label most similar to the others wins") {
  const auto enc = table_chair_encoder();
  SECTION("one mislabelled mask among three") {
    // Summed cosines: table 1 + 0 = 1 (twice), chair 0 + 0 = 0.
    const InstanceSemantics s = choose_instance_semantics({"chair", "table", "table"}, enc);
    CHECK(s.label == "table");
    CHECK(s.embedding.isApprox(vec3(1, 0, 0)));
  }
  SECTION("the medoid, not the most frequent label") {
    // operating table: 0.8 + 0.6 = 1.4; table: 0.8 + 0 = 0.8; chair: 0.6 + 0 = 0.6.
    const InstanceSemantics s =
        choose_instance_semantics({"table", "chair", "operating table"}, enc);
    CHECK(s.label == "operating table");
    CHECK(s.embedding.isApprox(vec3(0.8f, 0.6f, 0)));
  }
  SECTION("a duplicated label does not beat a closer medoid") {
    // chair 1 + 0 + 0.6 = 1.6 (twice), table 0 + 0 + 0.8 = 0.8, operating table
    // 0.6 + 0.8 + 0.6 = 2.0.
    const InstanceSemantics s =
        choose_instance_semantics({"chair", "table", "chair", "operating table"}, enc);
    CHECK(s.label == "operating table");
  }
  SECTION("a tie goes to the earliest mask") {
    // chair 0 + 0 + 1 = 1, table 0 + 1 + 0 = 1.
    CHECK(choose_instance_semantics({"chair", "table", "table", "chair"}, enc).label == "chair");
  }
}

TEST_CASE("two masks or fewer: the normalised average of their embeddings") {
  const auto enc = table_chair_encoder();
  const InstanceSemantics two = choose_instance_semantics({"table", "operating table"}, enc);
  // (1.8, 0.6, 0) / sqrt(3.6)
  CHECK(two.embedding.isApprox(vec3(0.948683f, 0.316228f, 0), 1e-5f));
  CHECK(two.label == "table");  // equally frequent: the first
  const InstanceSemantics opposite = choose_instance_semantics({"chair", "table"}, enc);
  CHECK(opposite.embedding.isApprox(vec3(0.707107f, 0.707107f, 0), 1e-5f));
  CHECK(opposite.label == "chair");
  const InstanceSemantics one = choose_instance_semantics({"chair"}, enc);
  CHECK(one.label == "chair");
  CHECK(one.embedding.isApprox(vec3(0, 1, 0)));
}

TEST_CASE("an instance without masks has no semantics") {
  const InstanceSemantics none = choose_instance_semantics({}, table_chair_encoder());
  CHECK(none.label.empty());
  REQUIRE(none.embedding.size() == 3);
  CHECK(none.embedding.norm() == 0.f);
}
