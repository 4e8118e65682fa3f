// bench_text_queries [--print-misses]: the lexical encoder (nodes/text/lexical_text_encoder.hpp)
// over graphs/vocabulary/or.yaml, scored on tests/data/text_queries/or_paraphrases.tsv (top-1
// class, dev and test halves), and the time one query takes to be mapped onto the classes once the
// encoder is loaded: each query is timed the first time it is seen (its words may still have to be
// read from WordNet) and again once warm; medians over the set. Writes
// bench/results/text_queries.{json,csv,svg}.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "base/svg.hpp"
#include "nodes/scene/context_prompt.hpp"
#include "nodes/text/lexical_text_encoder.hpp"
#include "nodes/text/query_set.hpp"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Seconds of one mapping of `text` onto the classes.
double time_query(const gslift::VocabularyMatcher& matcher, const std::string& text) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto ranked = matcher.rank(text);
  const auto t1 = std::chrono::steady_clock::now();
  if (ranked.empty()) std::abort();
  return std::chrono::duration<double>(t1 - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  using namespace gslift;
  const bool print_misses = argc > 1 && std::strcmp(argv[1], "--print-misses") == 0;
  const std::filesystem::path root = GSLIFT_SOURCE_DIR;
  const Vocabulary vocabulary = load_vocabulary(root / "graphs/vocabulary/or.yaml");
  const auto t0 = std::chrono::steady_clock::now();
  const LexicalTextEncoder encoder(vocabulary);
  const VocabularyMatcher matcher(encoder, vocabulary.class_names());
  const double load_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto queries =
      load_query_set(root / "tests/data/text_queries/or_paraphrases.tsv", vocabulary.class_names());

  std::vector<double> first, warm;
  for (const auto& q : queries) first.push_back(time_query(matcher, q.text));
  for (int repeat = 0; repeat < 20; ++repeat)
    for (const auto& q : queries) warm.push_back(time_query(matcher, q.text));
  const QuerySetScore score = score_query_set(matcher, queries);

  // Words that name nothing in an operating room: their best cosine is what match_threshold must
  // stay above.
  nlohmann::json unrelated = nlohmann::json::object();
  for (const char* text : {"toaster", "banana", "guitar", "elephant", "sailboat", "the red car",
                           "a bird on the roof", "snow"}) {
    const ClassMatch best = matcher.rank(text).front();
    unrelated[text] = {{"nearest", best.name}, {"score", best.score}};
    if (print_misses)
      std::printf("  unrelated: %.2f %s -> %s\n", best.score, text, best.name.c_str());
  }
  nlohmann::json answers = nlohmann::json::array();
  for (size_t i = 0; i < queries.size(); ++i)
    answers.push_back({{"query", queries[i].text},
                       {"split", queries[i].split},
                       {"expected", queries[i].expected},
                       {"top1", score.answers[i].name},
                       {"score", score.answers[i].score}});
  const double first_ms = 1e3 * median(first), warm_ms = 1e3 * median(warm);
  const double first_max_ms = 1e3 * *std::max_element(first.begin(), first.end());
  nlohmann::json out = {{"encoder", encoder.name()},
                        {"query_set", "tests/data/text_queries/or_paraphrases.tsv"},
                        {"dev",
                         {{"queries", score.dev_total},
                          {"top1", score.dev_top1},
                          {"accuracy", score.dev_accuracy()}}},
                        {"test",
                         {{"queries", score.test_total},
                          {"top1", score.test_top1},
                          {"accuracy", score.test_accuracy()}}},
                        {"misses", score.misses},
                        {"answers", answers},
                        {"unrelated", unrelated},
                        {"match_threshold", matcher.threshold()},
                        {"load_s", load_s},
                        {"query_ms",
                         {{"first_median", first_ms},
                          {"first_max", first_max_ms},
                          {"warm_median", warm_ms},
                          {"queries", queries.size()},
                          {"warm_repeats", 20}}}};
  const auto results = root / "bench/results";
  std::ofstream(results / "text_queries.json") << out.dump(2) << "\n";
  std::ofstream csv(results / "text_queries.csv");
  csv << "measure,value\n"
      << "dev_top1_accuracy," << score.dev_accuracy() << "\n"
      << "test_top1_accuracy," << score.test_accuracy() << "\n"
      << "query_ms_first_median," << first_ms << "\n"
      << "query_ms_first_max," << first_max_ms << "\n"
      << "query_ms_warm_median," << warm_ms << "\n"
      << "load_s," << load_s << "\n";

  // Two accuracy bars against the 75% target, and the latencies as text.
  Svg svg(360, 230, 12, true);
  const double base = 170, height = 140;
  svg.text(20, 20, "Offline encoder on the OR paraphrases (top-1)");
  const double target_y = base - 0.75 * height;
  svg.line(40, target_y, 300, target_y, "#c33", "stroke-dasharray='6 4'");
  svg.text(302, target_y + 4, "75%");
  const double acc[2] = {score.dev_accuracy(), score.test_accuracy()};
  const char* names[2] = {"dev", "test"};
  for (int i = 0; i < 2; ++i) {
    const double x = 70 + i * 120, h = acc[i] * height;
    svg.rect(x, base - h, 60, h, i ? "#2a6fb0" : "#9bbbd9");
    svg.text(x + 8, base - h - 4, Svg::number(100 * acc[i]) + "%");
    svg.text(x + 18, base + 16, names[i]);
  }
  char latency[160];
  std::snprintf(latency, sizeof latency, "query after load: median %.3f ms first, %.3f ms warm",
                first_ms, warm_ms);
  svg.text(20, 215, latency);
  std::ofstream(results / "text_queries.svg") << svg.str();

  std::printf("dev %d/%d  test %d/%d  query median %.3f ms first (max %.3f), %.3f ms warm\n",
              score.dev_top1, score.dev_total, score.test_top1, score.test_total, first_ms,
              first_max_ms, warm_ms);
  if (print_misses) {
    for (const auto& m : score.misses) std::printf("  %s\n", m.c_str());
    for (size_t i = 0; i < queries.size(); ++i)
      std::printf("  %s: %.2f %s\n", queries[i].split.c_str(), score.answers[i].score,
                  queries[i].text.c_str());
  }
  return 0;
}
