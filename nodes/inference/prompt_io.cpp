#include "nodes/inference/prompt_io.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "base/errors.hpp"
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
      throw InputError(where + ": '" + key + "' holds " + p.dump() + ", not an [x, y] pixel");
    out.emplace_back(static_cast<int>(std::floor(p[0].get<double>())),
                     static_cast<int>(std::floor(p[1].get<double>())));
  }
  return out;
}

}  // namespace

Prompt prompt_from_json(const nlohmann::json& j, const std::filesystem::path& base,
                        const std::string& where, size_t index) {
  if (!j.is_object()) throw InputError(where + ": a prompt is a JSON object, not " + j.dump());
  Prompt p;
  p.name = j.value("name", "prompt_" + std::to_string(index));
  if (!j.contains("view") || !j["view"].is_string())
    throw InputError(where + ": the prompt names no view (\"view\": \"<view name>\")");
  p.view = j["view"].get<std::string>();
  const std::string kind = j.value("kind", j.contains("mask") ? "mask" : "point");
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
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string() + ": not JSON (" + e.what() + ")");
  }
  if (j.is_object() && j.contains("prompts")) j = j["prompts"];
  if (!j.is_array()) throw InputError(path.string() + ": expected a list of prompts");
  PromptSet set;
  for (size_t k = 0; k < j.size(); ++k)
    set.prompts.push_back(prompt_from_json(j[k], path.parent_path(),
                                           path.string() + " prompt " + std::to_string(k), k));
  return set;
}

}  // namespace gslift
