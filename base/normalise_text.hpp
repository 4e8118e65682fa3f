// The canonical form labels are compared and looked up by (the table encoder, the query set, a
// VLM's labels against the class names): lower case, runs of whitespace collapsed to one space, no
// leading or trailing space.
#pragma once

#include <cctype>
#include <string>

namespace gslift {

inline std::string normalise_text(const std::string& text) {
  std::string out;
  bool pending_space = false;
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (std::isspace(c)) {
      pending_space = !out.empty();
      continue;
    }
    if (pending_space) out.push_back(' ');
    pending_space = false;
    out.push_back(static_cast<char>(std::tolower(c)));
  }
  return out;
}

}  // namespace gslift
