// The offline encoder that knows synonyms (issue 30): a text's embedding is its lexical score for
// every class of a vocabulary (lexical_matcher.hpp), followed by the hashing embedding of the text
// (hashing_text_encoder.hpp) weighted by what the classes leave unexplained, 1 - the best score:
//
//   encode(t) = normalise([s_1(t), ..., s_K(t), (1 - max_k s_k(t)) hashing(t)])
//
// A class name or alias is the pure unit vector of its class, so cosine(encode(t), encode(class k))
// = s_k(t) / |...|: the share of t that class k explains. A text near no class keeps its hashing
// part, so two unknown labels still compare by their spelling ("toaster" matches "toaster") and
// are orthogonal to every class.
#pragma once

#include <filesystem>

#include "nodes/scene/text_encoder.hpp"
#include "nodes/scene/vocabulary.hpp"
#include "nodes/text/hashing_text_encoder.hpp"
#include "nodes/text/lexical_matcher.hpp"

namespace gslift {

class LexicalTextEncoder : public TextEncoder {
 public:
  // Builds the index (reads WordNet for every class word); hashing_dim as HashingTextEncoder's.
  LexicalTextEncoder(const Vocabulary& vocabulary, int hashing_dim = 384);

  Eigen::VectorXf encode(const std::string& text) const override;
  int dim() const override;
  std::string name() const override { return "lexical:" + source_; }
  // Chosen on the dev half of tests/data/text_queries/or_paraphrases.tsv: its descriptive queries
  // ("person on the table") land at 0.41 and up, since their words match contexts at 0.35; words
  // that name nothing in an OR stay near 0 (bench/results/text_queries.json, "unrelated"), except
  // WordNet's other senses ("guitar" is an instrument, a "car" a machine).
  float match_threshold() const override { return 0.4f; }

  const LexicalIndex& index() const { return index_; }

 private:
  std::string source_;
  LexicalIndex index_;
  HashingTextEncoder hashing_;
};

}  // namespace gslift
