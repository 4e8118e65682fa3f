// The JSON files the chart programs read (sweep.json, run.json): a missing or unparsable file is
// a discarded value, which callers skip, since a sweep folder may hold unfinished runs.
#pragma once

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

namespace gslift::bench {

inline nlohmann::json read_json_or_discarded(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) return nlohmann::json();
  return nlohmann::json::parse(in, nullptr, false);
}

}  // namespace gslift::bench
