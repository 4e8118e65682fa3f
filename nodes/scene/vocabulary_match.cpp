#include "nodes/scene/vocabulary_match.hpp"

#include <algorithm>
#include <cstdio>

#include "base/errors.hpp"

namespace gslift {

VocabularyMatcher::VocabularyMatcher(const TextEncoder& encoder,
                                     std::vector<std::string> class_names)
    : encoder_(encoder), names_(std::move(class_names)), threshold_(encoder.match_threshold()) {
  if (names_.empty()) throw InputError("vocabulary match: no class names to match onto");
  embeddings_.resize(static_cast<Eigen::Index>(names_.size()), encoder.dim());
  for (size_t k = 0; k < names_.size(); ++k) embeddings_.row(k) = encoder.encode(names_[k]);
}

std::vector<ClassMatch> VocabularyMatcher::rank(const std::string& text) const {
  const Eigen::VectorXf q = encoder_.encode(text);
  std::vector<ClassMatch> out;
  for (size_t k = 0; k < names_.size(); ++k)
    out.push_back({names_[k], static_cast<int>(k), cosine(embeddings_.row(k).transpose(), q)});
  std::stable_sort(out.begin(), out.end(),
                   [](const ClassMatch& a, const ClassMatch& b) { return a.score > b.score; });
  return out;
}

std::optional<ClassMatch> VocabularyMatcher::match(const std::string& text) const {
  ClassMatch best = rank(text).front();
  if (best.score < threshold_) return std::nullopt;
  return best;
}

std::string VocabularyMatcher::explain_miss(const std::string& text) const {
  const std::vector<ClassMatch> ranked = rank(text);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f", threshold_);
  std::string out = "no class near '" + text + "' (threshold " + buf + "); nearest:";
  for (size_t i = 0; i < ranked.size() && i < 3; ++i) {
    std::snprintf(buf, sizeof buf, "%.2f", ranked[i].score);
    out += (i ? ", " : " ") + ranked[i].name + " (" + buf + ")";
  }
  return out;
}

}  // namespace gslift
