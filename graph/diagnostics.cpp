#include "graph/diagnostics.hpp"

namespace gslift {

std::string Diagnostic::str() const {
  std::string s = loc.str() + ": " + (severity == Severity::Error ? "error" : "warning") + "[" +
                  code + "]: " + message;
  if (!hint.empty()) s += " (" + hint + ")";
  return s;
}

void Diagnostics::error(SourceLoc loc, std::string code, std::string message, std::string hint) {
  list_.push_back(Diagnostic{Diagnostic::Severity::Error, std::move(loc), std::move(code),
                             std::move(message), std::move(hint)});
}

void Diagnostics::warning(SourceLoc loc, std::string code, std::string message, std::string hint) {
  list_.push_back(Diagnostic{Diagnostic::Severity::Warning, std::move(loc), std::move(code),
                             std::move(message), std::move(hint)});
}

bool Diagnostics::has_errors() const {
  for (const auto& d : list_)
    if (d.severity == Diagnostic::Severity::Error) return true;
  return false;
}

}  // namespace gslift
