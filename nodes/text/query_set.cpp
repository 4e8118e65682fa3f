#include "nodes/text/query_set.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "base/errors.hpp"
#include "base/normalise_text.hpp"

namespace gslift {

std::vector<LabelledQuery> load_query_set(const std::filesystem::path& path,
                                          const std::vector<std::string>& class_names) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot read the query set");
  std::vector<LabelledQuery> out;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const std::string where = path.string() + ":" + std::to_string(number);
    const size_t a = line.find('\t'), b = a == std::string::npos ? a : line.find('\t', a + 1);
    if (b == std::string::npos || line.find('\t', b + 1) != std::string::npos)
      throw InputError(where + ": expected \"query<TAB>class<TAB>dev|test\"");
    LabelledQuery q{line.substr(0, a), line.substr(a + 1, b - a - 1), line.substr(b + 1)};
    if (q.split != "dev" && q.split != "test")
      throw InputError(where + ": split '" + q.split + "' is neither dev nor test");
    const auto named = std::find_if(class_names.begin(), class_names.end(), [&](const auto& n) {
      return normalise_text(n) == normalise_text(q.expected);
    });
    if (named == class_names.end())
      throw InputError(where + ": '" + q.expected + "' is not a class of the vocabulary");
    q.expected = *named;  // the vocabulary's spelling, as the matcher answers
    out.push_back(std::move(q));
  }
  if (out.empty()) throw InputError(path.string() + ": no queries");
  return out;
}

QuerySetScore score_query_set(const VocabularyMatcher& matcher,
                              const std::vector<LabelledQuery>& queries) {
  QuerySetScore s;
  for (const LabelledQuery& q : queries) {
    const ClassMatch best = matcher.rank(q.text).front();
    s.answers.push_back(best);
    const bool right = best.name == q.expected;
    const bool dev = q.split == "dev";
    (dev ? s.dev_total : s.test_total) += 1;
    (dev ? s.dev_top1 : s.test_top1) += right ? 1 : 0;
    if (!right) {
      char score[32];
      std::snprintf(score, sizeof score, "%.2f", best.score);
      s.misses.push_back(q.split + ": '" + q.text + "' -> " + best.name + " (" + score +
                         "), expected " + q.expected);
    }
  }
  return s;
}

}  // namespace gslift
