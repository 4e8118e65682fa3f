// The built-in, deterministic text encoder: no model files, no network. Subword hashing in the
// fastText style: a text is lower-cased and split into words (runs of letters and digits); each
// word contributes its unigram and the character 3..5-grams of "<word>" (angle brackets mark the
// word boundaries, so prefixes and suffixes are distinct features). Every feature is hashed with
// 64-bit FNV-1a into one of dim buckets with a hash-derived sign (signed feature hashing,
// Weinberger et al. 2009, keeps collisions unbiased), and the vector is L2-normalised.
// Spelling variants ("anesthesia" / "anaesthesia") share most n-grams and stay close; unrelated
// words share few. It knows no synonyms ("doctor" vs "surgeon"): use a table encoder with real
// sentence embeddings for that.
#pragma once

#include "nodes/scene/text_encoder.hpp"

namespace gslift {

class HashingTextEncoder : public TextEncoder {
 public:
  // dim >= 1 (std::invalid_argument otherwise); 384 matches all-MiniLM-L6-v2's width.
  explicit HashingTextEncoder(int dim = 384);

  // A text without letters or digits encodes to the zero vector (cosine 0 with everything).
  Eigen::VectorXf encode(const std::string& text) const override;
  int dim() const override { return dim_; }
  std::string name() const override { return "hashing-" + std::to_string(dim_); }

 private:
  int dim_;
};

}  // namespace gslift
