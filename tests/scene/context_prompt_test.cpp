#include "nodes/scene/context_prompt.hpp"

#include "base/errors.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("the shipped OR vocabulary loads with the 12 classes and contexts") {
  const Vocabulary v =
      load_vocabulary(std::filesystem::path(GSLIFT_SOURCE_DIR) / "graphs/vocabulary/or.yaml");
  CHECK(v.class_names() == std::vector<std::string>{"operating table", "patient", "head surgeon",
                                                    "assistant surgeon", "circulating nurse",
                                                    "anaesthetist", "anesthesia machine",
                                                    "instrument table", "secondary table",
                                                    "monitor", "surgical lamp", "c-arm"});
  int people = 0;
  for (const auto& e : v.entities) {
    people += e.person;
    CHECK(e.person == !e.behaviour.empty());
  }
  CHECK(people == 5);
  // The prompt names every class with its contexts and asks for Qwen-VL grounding JSON.
  for (const auto& e : v.entities) {
    CHECK(v.prompt.find(e.name) != std::string::npos);
    CHECK(v.prompt.find(e.appearance) != std::string::npos);
  }
  CHECK(v.prompt.find("\"bbox_2d\": [x1, y1, x2, y2]") != std::string::npos);
  CHECK(v.prompt == build_prompt(v));
}

TEST_CASE("vocabulary errors name the file, line and what is missing") {
  const std::string missing_spatial =
      "classes:\n"
      "  - name: monitor\n"
      "    kind: object\n"
      "    appearance: a screen\n";
  CHECK_THROWS_WITH(parse_vocabulary(missing_spatial, "voc.yaml"),
                    Catch::StartsWith("voc.yaml:2:") && Catch::Contains("no spatial context"));
  const std::string person_without_behaviour =
      "classes:\n"
      "  - {name: nurse, kind: person, spatial: here, appearance: scrubs}\n";
  CHECK_THROWS_WITH(parse_vocabulary(person_without_behaviour, "v.yaml"),
                    Catch::Contains("class 'nurse' has no behaviour context"));
  const std::string object_with_behaviour =
      "classes:\n"
      "  - {name: lamp, kind: object, spatial: up, appearance: round, behaviour: shines}\n";
  CHECK_THROWS_WITH(parse_vocabulary(object_with_behaviour, "v.yaml"),
                    Catch::Contains("people only"));
  CHECK_THROWS_WITH(parse_vocabulary("classes:\n  - {name: a, kind: robot, spatial: s, "
                                     "appearance: a}\n",
                                     "v.yaml"),
                    Catch::Contains("kind 'robot'"));
  CHECK_THROWS_WITH(parse_vocabulary("classes:\n  - {name: a, kind: object, spatial: s, "
                                     "appearance: a, colour: red}\n",
                                     "v.yaml"),
                    Catch::Contains("unknown key 'colour'"));
  CHECK_THROWS_WITH(parse_vocabulary("classes:\n  - {name: a, kind: object, spatial: s, "
                                     "appearance: a}\n  - {name: A, kind: object, spatial: s, "
                                     "appearance: a}\n",
                                     "v.yaml"),
                    Catch::Contains("v.yaml:3:") && Catch::Contains("defined twice"));
  CHECK_THROWS_WITH(parse_vocabulary("classes:\n  - name: a\n    kind: object\n    spatial: s\n"
                                     "    spatial: t\n    appearance: a\n",
                                     "v.yaml"),
                    Catch::Contains("v.yaml:5:") && Catch::Contains("'spatial' appears twice"));
  CHECK_THROWS_AS(parse_vocabulary("nothing: here\n", "v.yaml"), InputError);
  CHECK_THROWS_AS(parse_vocabulary("classes: [\n", "v.yaml"), InputError);
  CHECK_THROWS_WITH(load_vocabulary("/nonexistent/or.yaml"),
                    Catch::Contains("/nonexistent/or.yaml"));
}
