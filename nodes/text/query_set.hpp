// A labelled set of free-worded queries (tests/data/text_queries/or_paraphrases.tsv): lines
// "query<TAB>class<TAB>split", split dev (for choosing) or test (for reporting); '#' comments and
// blank lines skipped. Scored as top-1 class accuracy through a VocabularyMatcher.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "nodes/scene/vocabulary_match.hpp"

namespace gslift {

struct LabelledQuery {
  std::string text, expected, split;
};

// Throws InputError naming file:line for a line without three fields, a split other than dev /
// test, or a class not in `class_names` (compared without case); and when the file is unreadable or
// empty.
std::vector<LabelledQuery> load_query_set(const std::filesystem::path& path,
                                          const std::vector<std::string>& class_names);

struct QuerySetScore {
  int dev_total = 0, dev_top1 = 0, test_total = 0, test_top1 = 0;
  // Test and dev queries whose top-1 class was wrong: "query -> got (score), expected".
  std::vector<std::string> misses;
  std::vector<ClassMatch> answers;  // per query, in order: its top-1 class
  double dev_accuracy() const { return dev_total ? double(dev_top1) / dev_total : 0; }
  double test_accuracy() const { return test_total ? double(test_top1) / test_total : 0; }
};

QuerySetScore score_query_set(const VocabularyMatcher& matcher,
                              const std::vector<LabelledQuery>& queries);

}  // namespace gslift
