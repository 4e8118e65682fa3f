// Collecting diagnostics while a graph is read and validated: every stage appends to one list
// so that all problems are reported together, not only the first.
#pragma once

#include <string>
#include <vector>

#include "graph/loader.hpp"

namespace gslift {

class Diagnostics {
 public:
  void error(SourceLoc loc, std::string code, std::string message, std::string hint = {});
  void warning(SourceLoc loc, std::string code, std::string message, std::string hint = {});

  bool has_errors() const;
  const std::vector<Diagnostic>& list() const { return list_; }

 private:
  std::vector<Diagnostic> list_;
};

}  // namespace gslift
