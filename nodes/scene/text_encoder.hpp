// The text encoder that travels on ports (LangOR §1.1): cluster labels and user queries go through
// the same encoder, so retrieval is text-to-text cosine similarity. The encoders themselves live
// in nodes/text/; association and inference only need this interface.
#pragma once

#include <string>

#include <Eigen/Core>

#include "base/port_type.hpp"

namespace gslift {

class TextEncoder {
 public:
  virtual ~TextEncoder() = default;
  // An L2-normalised embedding of `text` (dim() entries).
  virtual Eigen::VectorXf encode(const std::string& text) const = 0;
  virtual int dim() const = 0;
  // Short description for run records, e.g. "hashing-384" or "table:<file>".
  virtual std::string name() const = 0;
  // The cosine similarity from which a text counts as meaning a class (nodes/text/
  // vocabulary_match.hpp): what an encoder's unrelated texts stay below.
  virtual float match_threshold() const { return 0.5f; }
};

GSLIFT_PORT_TYPE(TextEncoder, "TextEncoder");

// Cosine similarity of two embeddings (0 when either is zero).
float cosine(const Eigen::VectorXf& a, const Eigen::VectorXf& b);

}  // namespace gslift
