// Capture paths with a scheme ("embedded:or?seed=3"): a provider registered for the scheme turns
// the rest of the string into a folder on disk (generating it when needed), which is then read
// like any other capture. nodes/synth registers "embedded".
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace gslift {

// `spec` is the text after "<scheme>:" ("or?seed=3" for "embedded:or?seed=3").
using CaptureProvider = std::function<std::filesystem::path(const std::string& spec)>;

// Registers (or replaces) the provider of `scheme` (lowercase, at least two characters, so that
// a Windows drive letter is never taken for a scheme). Thread-safe.
void register_capture_provider(const std::string& scheme, CaptureProvider provider);

// A path with a scheme prefix is handed to that scheme's provider; any other string is a plain
// path, returned as it is. An unknown scheme is an InputError listing the known ones.
std::filesystem::path resolve_capture_path(const std::string& path);

}  // namespace gslift
