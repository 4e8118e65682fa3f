// Queries in the user's words through inference.text_query's selection and eval.langor's choice
// of query per class (issue 30), with the lexical encoder over the OR vocabulary.
#include <catch2/catch.hpp>

#include "nodes/eval/langor_eval.hpp"
#include "nodes/inference/text_query.hpp"
#include "nodes/scene/context_prompt.hpp"
#include "nodes/text/lexical_text_encoder.hpp"

using namespace gslift;

namespace {

// One instance per class, labelled with its class name, as association gives them.
struct OrInstances {
  Vocabulary vocabulary =
      load_vocabulary(std::filesystem::path(GSLIFT_SOURCE_DIR) / "graphs/vocabulary/or.yaml");
  LexicalTextEncoder encoder{vocabulary};
  InstanceSet instances;
  OrInstances() {
    const auto names = vocabulary.class_names();
    instances.prototypes = Eigen::MatrixXf::Zero(static_cast<Eigen::Index>(names.size()), 1);
    instances.semantics.resize(static_cast<Eigen::Index>(names.size()), encoder.dim());
    for (size_t k = 0; k < names.size(); ++k) {
      instances.semantics.row(k) = encoder.encode(names[k]).transpose();
      instances.labels.push_back(names[k]);
    }
  }
  int index_of(const std::string& name) const {
    const auto names = vocabulary.class_names();
    return static_cast<int>(std::find(names.begin(), names.end(), name) - names.begin());
  }
};

}  // namespace

TEST_CASE("text query: the user's words select the instances of their classes") {
  const OrInstances s;
  REQUIRE(s.instances.size() == 12);
  TextQueryOptions options;
  options.vocabulary = s.vocabulary.class_names();
  TextQueryResults r;
  r.queries = {"ventilator", "nurse", "the person lying on the table", "toaster"};
  select_instances(s.instances, s.encoder, options, r);
  CHECK(r.instances[0] == std::vector<int>{s.index_of("anesthesia machine")});
  CHECK(r.instances[1] == std::vector<int>{s.index_of("circulating nurse")});
  CHECK(r.instances[2] == std::vector<int>{s.index_of("patient")});
  CHECK(r.instances[3].empty());
  CHECK(r.query_classes ==
        std::vector<std::string>{"anesthesia machine", "circulating nurse", "patient", ""});
  CHECK(r.query_class_scores[0] >= s.encoder.match_threshold());
  CHECK(r.query_class_scores[3] < s.encoder.match_threshold());

  // The class names themselves, as the eval's default query set: each selects its own instance.
  TextQueryResults names;
  names.queries = s.vocabulary.class_names();
  select_instances(s.instances, s.encoder, options, names);
  for (size_t q = 0; q < names.queries.size(); ++q) {
    INFO(names.queries[q]);
    CHECK(names.instances[q] == std::vector<int>{static_cast<int>(q)});
    CHECK(names.query_classes[q] == names.queries[q]);
  }
}

TEST_CASE("eval.langor: a class is scored through the query that names or lands on it") {
  TextQueryResults r;
  r.queries = {"ventilator", "patient", "toaster"};
  r.query_classes = {"anesthesia machine", "patient", ""};
  r.query_class_scores = {0.9f, 1.f, 0.1f};
  CHECK(query_for_class(r, "anesthesia machine") == std::optional<size_t>(0));
  CHECK(query_for_class(r, "patient") == std::optional<size_t>(1));
  CHECK_FALSE(query_for_class(r, "monitor"));
  Capture capture;
  capture.classes = {{0, "background"}, {1, "patient"}, {2, "monitor"}, {3, "anesthesia machine"}};
  CHECK(langor_unqueried_classes(r, capture) == std::vector<std::string>{"monitor"});
}
