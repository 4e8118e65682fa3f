#include "nodes/text/lexical_text_encoder.hpp"

#include <algorithm>

namespace gslift {

LexicalTextEncoder::LexicalTextEncoder(const Vocabulary& vocabulary, int hashing_dim)
    : source_(vocabulary.source), index_(build_lexical_index(vocabulary)), hashing_(hashing_dim) {}

int LexicalTextEncoder::dim() const {
  return static_cast<int>(index_.classes.size()) + hashing_.dim();
}

Eigen::VectorXf LexicalTextEncoder::encode(const std::string& text) const {
  const std::vector<float> scores = lexical_scores(index_, text);
  const int k = static_cast<int>(scores.size());
  Eigen::VectorXf v(dim());
  float best = 0;
  for (int i = 0; i < k; ++i) {
    v[i] = scores[i];
    best = std::max(best, scores[i]);
  }
  v.tail(hashing_.dim()) = (1.f - best) * hashing_.encode(text);
  const float norm = v.norm();
  if (norm > 0) v /= norm;
  return v;
}

}  // namespace gslift
