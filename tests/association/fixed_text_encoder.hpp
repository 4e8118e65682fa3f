// A TextEncoder with hand-picked embeddings, so association tests can compute cosines by hand.
#pragma once

#include <map>
#include <string>

#include "nodes/scene/text_encoder.hpp"

namespace gslift::test {

class FixedTextEncoder : public TextEncoder {
 public:
  explicit FixedTextEncoder(std::map<std::string, Eigen::VectorXf> table)
      : table_(std::move(table)) {}
  Eigen::VectorXf encode(const std::string& text) const override { return table_.at(text); }
  int dim() const override { return static_cast<int>(table_.begin()->second.size()); }
  std::string name() const override { return "fixed"; }

 private:
  std::map<std::string, Eigen::VectorXf> table_;
};

inline Eigen::VectorXf vec3(float a, float b, float c) {
  // Filled element by element: converting a Vector3f made g++ 12 warn about the 16-float packet
  // load of a path that is never taken for three elements (-Warray-bounds under AVX-512).
  Eigen::VectorXf v(3);
  v << a, b, c;
  return v;
}

}  // namespace gslift::test
