#include "nodes/inference/prompt_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <yaml-cpp/yaml.h>
#include <opencv2/imgcodecs.hpp>

#include "base/errors.hpp"
#include "base/json_read.hpp"
#include "base/utf8.hpp"
#include "nodes/scene/image_io.hpp"

namespace gslift {
namespace {

std::vector<cv::Point> pixel_list(const nlohmann::json& j, const char* key,
                                  const std::string& where) {
  std::vector<cv::Point> out;
  if (!j.contains(key)) return out;
  const nlohmann::json& list = j[key];
  if (!list.is_array()) throw InputError(where + ": '" + key + "' must be a list of [x, y] pixels");
  for (const auto& p : list) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
      throw InputError(where + ": '" + key + "' holds " + printable(p.dump()) +
                       ", not an [x, y] pixel");
    // Converting a double outside int's range is undefined behaviour ([[1e308, 0]] became
    // (-2147483648, 0)): such a pixel lies outside every image, and is refused as one.
    const double x = std::floor(p[0].get<double>()), y = std::floor(p[1].get<double>());
    constexpr double kLimit = 2147483648.0;  // 2^31
    if (!(x >= -kLimit && x < kLimit && y >= -kLimit && y < kLimit))
      throw InputError(where + ": '" + key + "' holds " + printable(p.dump()) +
                       ", a pixel outside any image");
    out.emplace_back(static_cast<int>(x), static_cast<int>(y));
  }
  return out;
}

std::string string_field(const nlohmann::json& j, const char* key, const std::string& fallback,
                         const std::string& where) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_string())
    throw InputError(where + ": '" + key + "' must be a string, not " + j[key].dump());
  return j[key].get<std::string>();
}

// YAML as JSON: maps, sequences, and scalars as numbers or booleans where they read as such
// (a leading zero keeps a scalar a string: view names like 000000).
nlohmann::json yaml_to_json(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Map: {
      nlohmann::json j = nlohmann::json::object();
      for (const auto& kv : n) j[kv.first.as<std::string>()] = yaml_to_json(kv.second);
      return j;
    }
    case YAML::NodeType::Sequence: {
      nlohmann::json j = nlohmann::json::array();
      for (const auto& v : n) j.push_back(yaml_to_json(v));
      return j;
    }
    case YAML::NodeType::Scalar: {
      const std::string t = n.Scalar();
      if (n.Tag() == "!") return t;  // quoted
      if (t == "true" || t == "false") return t == "true";
      const bool leading_zero = t.size() > 1 && t[0] == '0' && t[1] != '.';
      if (!leading_zero && !t.empty()) {
        char* end = nullptr;
        const double v = std::strtod(t.c_str(), &end);
        if (end == t.c_str() + t.size()) return v;
      }
      return t;
    }
    default:
      return nullptr;
  }
}

}  // namespace

Prompt prompt_from_json(const nlohmann::json& j, const std::filesystem::path& base,
                        const std::string& where, size_t index,
                        const std::vector<std::string>& extra_fields) {
  if (!j.is_object()) throw InputError(where + ": a prompt is a JSON object, not " + j.dump());
  static const std::vector<std::string> fields = {"name",     "kind",     "view",
                                                  "positive", "negative", "mask"};
  for (const auto& item : j.items())
    if (std::find(fields.begin(), fields.end(), item.key()) == fields.end() &&
        std::find(extra_fields.begin(), extra_fields.end(), item.key()) == extra_fields.end())
      throw InputError(where + ": unknown field '" + item.key() +
                       "' (a prompt has name, kind, view, positive, negative, mask)");
  Prompt p;
  p.name = string_field(j, "name", "prompt_" + std::to_string(index), where);
  if (!j.contains("view"))
    throw InputError(where + ": the prompt names no view (\"view\": \"<view name>\")");
  p.view = string_field(j, "view", "", where);
  const std::string kind = string_field(j, "kind", j.contains("mask") ? "mask" : "point", where);
  try {
    p.kind = parse_enum(kind, prompt_kind_names(), "kind");
  } catch (const std::invalid_argument& e) {
    throw InputError(where + ": " + e.what());
  }
  p.positive = pixel_list(j, "positive", where);
  p.negative = pixel_list(j, "negative", where);
  if (p.kind == PromptKind::Mask || p.kind == PromptKind::Sam) {
    if (!j.contains("mask") || !j["mask"].is_string())
      throw InputError(where + ": a " + kind + " prompt needs \"mask\": \"<png file>\"");
    std::filesystem::path file = j["mask"].get<std::string>();
    if (file.is_relative()) file = base / file;
    cv::Mat m;
    try {
      m = read_image(file, cv::IMREAD_GRAYSCALE);
    } catch (const InputError& e) {
      throw InputError(where + ": cannot read the mask image: " + e.what());
    }
    p.mask = m > 127;
  }
  return p;
}

PromptSet read_prompt_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open the prompt file " + path.string());
  std::stringstream text;
  text << in.rdbuf();
  const std::string ext = path.extension().string();
  nlohmann::json j;
  if (ext == ".yaml" || ext == ".yml") {
    try {
      j = yaml_to_json(YAML::Load(text.str()));
    } catch (const YAML::Exception& e) {
      throw InputError(path.string() + ": not YAML (" + e.what() + ")");
    }
  } else {
    try {
      j = parse_json(text.str());
    } catch (const nlohmann::json::exception& e) {
      throw InputError(path.string() + ": not JSON (" + e.what() + ")");
    }
  }
  if (j.is_object() && j.contains("prompts")) j = j["prompts"];
  if (!j.is_array())
    throw InputError(path.string() + ": expected a list of prompts (or \"prompts\": [...])");
  PromptSet set;
  for (size_t k = 0; k < j.size(); ++k)
    set.prompts.push_back(prompt_from_json(j[k], path.parent_path(),
                                           path.string() + " prompt " + std::to_string(k), k));
  return set;
}

}  // namespace gslift
