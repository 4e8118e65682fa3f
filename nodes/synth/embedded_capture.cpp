#include "nodes/synth/embedded_capture.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "base/cache_root.hpp"
#include "base/errors.hpp"
#include "base/hash.hpp"

namespace gslift::synth {

namespace fs = std::filesystem;

fs::path cache_root() {
  return user_cache_root();
}

OrCaptureSettings parse_embedded_spec(const std::string& spec) {
  const auto q = spec.find('?');
  const std::string scene = spec.substr(0, q);
  if (scene != "or") {
    throw InputError("embedded:" + spec + ": unknown embedded scene '" + scene +
                     "' (known: or, e.g. embedded:or?seed=3&phase=closing&preset=hard)");
  }
  std::vector<std::pair<std::string, std::string>> entries;
  if (q != std::string::npos) {
    const std::string query = spec.substr(q + 1);
    size_t start = 0;
    while (start <= query.size()) {
      const size_t end = std::min(query.find('&', start), query.size());
      const std::string item = query.substr(start, end - start);
      const auto eq = item.find('=');
      if (eq == std::string::npos || eq == 0) {
        throw InputError("embedded:" + spec + ": expected name=value, got '" + item + "'");
      }
      entries.emplace_back(item.substr(0, eq), item.substr(eq + 1));
      start = end + 1;
    }
  }
  try {
    return make_settings(entries);
  } catch (const std::invalid_argument& e) {
    throw InputError("embedded:" + spec + ": " + e.what());
  }
}

fs::path cached_capture_folder(const OrCaptureSettings& settings, const fs::path& cache) {
  std::string text = "gslift.synth/v1\n";
  for (const auto& [k, v] : settings_entries(settings)) text += k + "=" + v + "\n";
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(fnv1a64(text)));
  return cache / "embedded" / (capture_name(settings) + "-" + hex);
}

fs::path ensure_cached_capture(const OrCaptureSettings& settings, const fs::path& cache) {
  const fs::path folder = cached_capture_folder(settings, cache);
  if (fs::exists(folder / "capture.yaml")) return folder;
  try {
    write_or_capture(settings, folder);
  } catch (...) {
    // Another process may have generated the same capture meanwhile: that one is as good.
    if (fs::exists(folder / "capture.yaml")) return folder;
    throw;
  }
  return folder;
}

}  // namespace gslift::synth
