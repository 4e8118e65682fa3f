// Text encoders behind one interface (LangOR §1.1): cluster labels and user queries go through
// the same encoder, so retrieval is text-to-text cosine similarity.
#pragma once

#include <string>

#include <Eigen/Core>

#include "runtime/value.hpp"

namespace gslift {

class TextEncoder {
 public:
  virtual ~TextEncoder() = default;
  // An L2-normalised embedding of `text` (dim() entries).
  virtual Eigen::VectorXf encode(const std::string& text) const = 0;
  virtual int dim() const = 0;
  // Short description for run records, e.g. "hashing-384" or "table:<file>".
  virtual std::string name() const = 0;
};

GSLIFT_PORT_TYPE(TextEncoder, "TextEncoder");

// The canonical form both encoders look texts up by: lower case, runs of whitespace collapsed to
// one space, no leading or trailing space.
std::string normalise_text(const std::string& text);

// Cosine similarity of two embeddings (0 when either is zero).
float cosine(const Eigen::VectorXf& a, const Eigen::VectorXf& b);

}  // namespace gslift
