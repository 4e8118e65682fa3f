#include "nodes/ingest/capture_provider.hpp"

#include <map>
#include <mutex>

#include "base/errors.hpp"

namespace gslift {
namespace {

struct Providers {
  std::mutex mutex;
  std::map<std::string, CaptureProvider> by_scheme;
};

Providers& providers() {
  static Providers p;
  return p;
}

// The scheme of "scheme:rest": [a-z][a-z0-9+.-]+ before the first ':', else "".
std::string scheme_of(const std::string& path) {
  const size_t colon = path.find(':');
  if (colon == std::string::npos || colon < 2) return {};
  for (size_t i = 0; i < colon; ++i) {
    const char c = path[i];
    const bool ok = (c >= 'a' && c <= 'z') ||
                    (i > 0 && ((c >= '0' && c <= '9') || c == '+' || c == '.' || c == '-'));
    if (!ok) return {};
  }
  return path.substr(0, colon);
}

}  // namespace

void register_capture_provider(const std::string& scheme, CaptureProvider provider) {
  if (scheme_of(scheme + ":") != scheme)
    throw std::invalid_argument("invalid capture scheme '" + scheme + "'");
  std::lock_guard<std::mutex> lock(providers().mutex);
  providers().by_scheme[scheme] = std::move(provider);
}

std::filesystem::path resolve_capture_path(const std::string& path) {
  const std::string scheme = scheme_of(path);
  if (scheme.empty()) return path;
  CaptureProvider provider;
  std::string known;
  {
    std::lock_guard<std::mutex> lock(providers().mutex);
    auto it = providers().by_scheme.find(scheme);
    if (it != providers().by_scheme.end()) provider = it->second;
    for (const auto& [name, fn] : providers().by_scheme)
      known += (known.empty() ? "" : ", ") + name + ":";
  }
  if (!provider)
    throw InputError(path + ": unknown capture scheme '" + scheme +
                     ":'; known: " + (known.empty() ? "none" : known));
  return provider(path.substr(scheme.size() + 1));
}

}  // namespace gslift
