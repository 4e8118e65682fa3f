#include "graph/diagnostics.hpp"

#include "base/utf8.hpp"

namespace gslift {

namespace {

// A diagnostic quotes the graph file and the command line: a 10 MB node type or a value holding a
// terminal escape would otherwise reach stderr whole and raw. The sites quote through printable;
// this bounds what any site forgets (quotes already escaped pass unchanged).
constexpr size_t kMaxDiagnosticBytes = 4 * kMaxQuotedBytes;

std::string bounded(const std::string& text) {
  return printable(text, kMaxDiagnosticBytes);
}

}  // namespace

std::string Diagnostic::str() const {
  std::string s = loc.str() + ": " + (severity == Severity::Error ? "error" : "warning") + "[" +
                  code + "]: " + message;
  if (!hint.empty()) s += " (" + hint + ")";
  return s;
}

void Diagnostics::error(SourceLoc loc, std::string code, std::string message, std::string hint) {
  list_.push_back(Diagnostic{Diagnostic::Severity::Error, std::move(loc), std::move(code),
                             bounded(message), bounded(hint)});
}

void Diagnostics::warning(SourceLoc loc, std::string code, std::string message, std::string hint) {
  list_.push_back(Diagnostic{Diagnostic::Severity::Warning, std::move(loc), std::move(code),
                             bounded(message), bounded(hint)});
}

bool Diagnostics::has_errors() const {
  for (const auto& d : list_)
    if (d.severity == Diagnostic::Severity::Error) return true;
  return false;
}

}  // namespace gslift
