// Embedded captures ("embedded:or?seed=3&phase=closing&preset=hard"): generated on first use
// into a cache folder keyed by every setting, then read like any other capture
// (docs/capture_format.md). Generation is atomic (temporary folder + rename), so concurrent runs
// and interrupted runs never see a half-written capture.
#pragma once

#include <filesystem>
#include <string>

#include "nodes/synth/or_capture.hpp"

namespace gslift::synth {

// base/cache_root.hpp's user_cache_root(): $GSLIFT_CACHE, else $XDG_CACHE_HOME/gslift, else
// $HOME/.cache/gslift.
std::filesystem::path cache_root();

// Settings of the spec after "embedded:": "or", optionally followed by "?name=value&..." with
// the names of make_settings (seed, phase, views, width, height, preset, knobs). Throws
// InputError naming the spec and the bad setting.
OrCaptureSettings parse_embedded_spec(const std::string& spec);

// <cache>/embedded/<capture name>-<16 hex digits of a hash of settings_entries>.
std::filesystem::path cached_capture_folder(const OrCaptureSettings& settings,
                                            const std::filesystem::path& cache = cache_root());

// The cached capture folder, generated first when it does not exist yet.
std::filesystem::path ensure_cached_capture(const OrCaptureSettings& settings,
                                            const std::filesystem::path& cache = cache_root());

}  // namespace gslift::synth
