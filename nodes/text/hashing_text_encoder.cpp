#include "nodes/text/hashing_text_encoder.hpp"

#include <cctype>
#include <stdexcept>
#include <vector>

#include "base/hash.hpp"

namespace gslift {
namespace {

std::vector<std::string> words_of(const std::string& text) {
  std::vector<std::string> words;
  std::string current;
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (std::isalnum(c) || c >= 0x80) {  // keep UTF-8 bytes inside words
      current.push_back(static_cast<char>(std::tolower(c)));
    } else if (!current.empty()) {
      words.push_back(current);
      current.clear();
    }
  }
  if (!current.empty()) words.push_back(current);
  return words;
}

}  // namespace

HashingTextEncoder::HashingTextEncoder(int dim) : dim_(dim) {
  if (dim < 1) throw std::invalid_argument("HashingTextEncoder: dim must be >= 1");
}

Eigen::VectorXf HashingTextEncoder::encode(const std::string& text) const {
  Eigen::VectorXf v = Eigen::VectorXf::Zero(dim_);
  auto add = [&](const std::string& feature) {
    const uint64_t h = fnv1a64(feature);
    // Bucket from the low bits, sign from the top bit: independent enough for FNV-1a.
    v[static_cast<int>(h % static_cast<uint64_t>(dim_))] += (h >> 63) ? -1.f : 1.f;
  };
  for (const std::string& word : words_of(text)) {
    add("w:" + word);  // prefixed so a 3-letter word and its 3-gram are different features
    const std::string marked = "<" + word + ">";
    for (size_t n = 3; n <= 5; ++n)
      for (size_t i = 0; i + n <= marked.size(); ++i) add(marked.substr(i, n));
  }
  const float norm = v.norm();
  if (norm > 0) v /= norm;
  return v;
}

}  // namespace gslift
