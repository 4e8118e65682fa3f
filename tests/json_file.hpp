// Reading a JSON file a test's run wrote (run.json, _summary.json, ...).
#pragma once

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

namespace gslift::test {

inline nlohmann::json read_json(const std::filesystem::path& f) {
  std::ifstream in(f);
  return nlohmann::json::parse(in);
}

}  // namespace gslift::test
