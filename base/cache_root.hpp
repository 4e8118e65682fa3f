// The user's gslift cache folder, one place for everything gslift keeps between runs: generated
// embedded captures (<root>/embedded/, nodes/synth) and the stage cache (<root>/stages/,
// runtime/stage_cache.hpp).
#pragma once

#include <cstdlib>
#include <filesystem>

namespace gslift {

// $GSLIFT_CACHE, else $XDG_CACHE_HOME/gslift, else $HOME/.cache/gslift (./.cache/gslift without
// HOME).
inline std::filesystem::path user_cache_root() {
  if (const char* c = std::getenv("GSLIFT_CACHE"); c && *c) return c;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
    return std::filesystem::path(x) / "gslift";
  if (const char* h = std::getenv("HOME"); h && *h)
    return std::filesystem::path(h) / ".cache" / "gslift";
  return std::filesystem::path(".cache") / "gslift";
}

}  // namespace gslift
