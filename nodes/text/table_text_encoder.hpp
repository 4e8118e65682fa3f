// Precomputed embeddings from a file the user provides (e.g. all-MiniLM-L6-v2 sentence
// embeddings of the vocabulary and the queries, 384-d), so that gslift needs no neural network at
// run time. Two formats:
//   text (any extension but .json): one entry per line, "label<TAB>v1 v2 ... vD"; blank lines
//     and lines starting with '#' are skipped;
//   JSON (.json): {"label": [v1, ..., vD], ...}.
// Labels are matched after normalise_text (case and spacing do not matter). Vectors are
// L2-normalised on load.
//
// Unknown text is an error listing the known entries [decision]: falling back to the hashing
// encoder would compare vectors from two unrelated embedding spaces and return confident
// nonsense; the user should add the missing entry to the file instead.
#pragma once

#include <filesystem>
#include <map>
#include <vector>

#include "nodes/scene/text_encoder.hpp"

namespace gslift {

class TableTextEncoder : public TextEncoder {
 public:
  // Throws InputError naming the file (and line for the text format) on: unreadable file, a line
  // without a tab, a non-numeric value, rows of different dimensions, a duplicate label, a zero
  // vector, or no entries.
  static TableTextEncoder load(const std::filesystem::path& path);

  // Throws InputError for text not in the table, listing the known labels.
  Eigen::VectorXf encode(const std::string& text) const override;
  int dim() const override { return dim_; }
  std::string name() const override { return "table:" + source_; }

  bool contains(const std::string& text) const;
  std::vector<std::string> labels() const;  // normalised, sorted

 private:
  std::string source_;
  int dim_ = 0;
  std::map<std::string, Eigen::VectorXf> table_;
};

}  // namespace gslift
