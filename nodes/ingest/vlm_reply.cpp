#include "nodes/ingest/vlm_reply.hpp"

#include <algorithm>
#include <stdexcept>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "base/errors.hpp"
#include "base/json_read.hpp"

namespace gslift {
namespace {

using nlohmann::json;

// The text inside the first ``` fence (after its language tag), or all of it without fences.
std::string unfenced(const std::string& text) {
  const size_t open = text.find("```");
  if (open == std::string::npos) return text;
  size_t start = text.find('\n', open);
  start = start == std::string::npos ? open + 3 : start + 1;
  const size_t close = text.find("```", start);
  return text.substr(start, close == std::string::npos ? std::string::npos : close - start);
}

// The first balanced [...] or {...} of `s`, skipping brackets inside JSON strings.
std::string first_json_value(const std::string& s, const std::string& where) {
  const size_t begin = s.find_first_of("[{");
  if (begin == std::string::npos) throw InputError(where + ": no JSON array or object in reply");
  int depth = 0;
  bool in_string = false, escaped = false;
  for (size_t i = begin; i < s.size(); ++i) {
    const char c = s[i];
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      ++depth;
    } else if ((c == ']' || c == '}') && --depth == 0) {
      return s.substr(begin, i - begin + 1);
    }
  }
  throw InputError(where + ": unterminated JSON in reply");
}

}  // namespace

const EnumNames<VlmCoords>& vlm_coords_names() {
  static const EnumNames<VlmCoords> names = {{VlmCoords::Norm1000, "norm1000"},
                                             {VlmCoords::ResizedAbs, "resized_abs"},
                                             {VlmCoords::Pixels, "pixels"}};
  return names;
}

std::vector<Box> parse_vlm_reply(const std::string& text, const VlmFrame& frame, int round,
                                 const std::string& source) {
  const std::string where = source + " (round " + std::to_string(round) + ")";
  json reply;
  try {
    reply = parse_json(first_json_value(unfenced(text), where));
  } catch (const json::exception& e) {
    throw InputError(where + ": invalid JSON: " + e.what());
  }
  if (reply.is_object()) reply = json::array({reply});

  double sx = 1, sy = 1;
  switch (frame.coords) {
    case VlmCoords::Norm1000:
      sx = frame.image_width / 1000.0;
      sy = frame.image_height / 1000.0;
      break;
    case VlmCoords::ResizedAbs:
      if (frame.input_width <= 0 || frame.input_height <= 0)
        throw InputError(where + ": resized_abs coordinates need the VLM input size");
      sx = static_cast<double>(frame.image_width) / frame.input_width;
      sy = static_cast<double>(frame.image_height) / frame.input_height;
      break;
    case VlmCoords::Pixels:
      sx = sy = frame.pixel_scale;
      break;
    case VlmCoords::Auto:
      throw std::logic_error("parse_vlm_reply: coordinate space 'auto' was not resolved");
  }
  std::vector<Box> boxes;
  int degenerate = 0;
  for (size_t i = 0; i < reply.size(); ++i) {
    const json& e = reply[i];
    const std::string item = where + " item " + std::to_string(i);
    if (!e.is_object()) throw InputError(item + ": expected an object with bbox_2d");
    const json* bbox = e.contains("bbox_2d") ? &e["bbox_2d"]
                       : e.contains("bbox")  ? &e["bbox"]
                                             : nullptr;
    if (!bbox) throw InputError(item + ": no bbox_2d");
    if (!bbox->is_array() || bbox->size() != 4 ||
        !std::all_of(bbox->begin(), bbox->end(), [](const json& x) { return x.is_number(); }))
      throw InputError(item + ": bbox_2d must be 4 numbers [x1, y1, x2, y2]");
    auto clamp = [](double v, int hi) { return static_cast<float>(std::clamp(v, 0.0, 1.0 * hi)); };
    Box b;
    b.x1 = clamp((*bbox)[0].get<double>() * sx, frame.image_width);
    b.y1 = clamp((*bbox)[1].get<double>() * sy, frame.image_height);
    b.x2 = clamp((*bbox)[2].get<double>() * sx, frame.image_width);
    b.y2 = clamp((*bbox)[3].get<double>() * sy, frame.image_height);
    if (e.contains("label") && e["label"].is_string()) b.label = e["label"].get<std::string>();
    if (e.contains("score") && e["score"].is_number()) b.score = e["score"].get<float>();
    b.round = round;
    b.source_index = static_cast<int>(i);
    if (b.area() <= 0) {
      ++degenerate;
      continue;
    }
    boxes.push_back(std::move(b));
  }
  if (degenerate > 0)
    spdlog::warn("{}: dropped {} degenerate box(es) (empty after clamping to the image)", where,
                 degenerate);
  return boxes;
}

ViewReplies parse_view_replies(const std::string& view, const std::vector<std::string>& replies,
                               const VlmFrame& frame,
                               const std::function<std::string(int round)>& source) {
  ViewReplies out;
  out.boxes.view = view;
  out.boxes.rounds = static_cast<int>(replies.size());
  std::string last_error;
  for (size_t k = 0; k < replies.size(); ++k) {
    const int round = static_cast<int>(k);
    try {
      for (Box& b : parse_vlm_reply(replies[k], frame, round, source(round)))
        out.boxes.boxes.push_back(std::move(b));
    } catch (const InputError& e) {
      ++out.unparsed;
      last_error = e.what();
      spdlog::warn("VLM round skipped: {}", last_error);
    }
  }
  if (!replies.empty() && out.unparsed == static_cast<int>(replies.size()))
    throw InputError("view '" + view + "': none of its " + std::to_string(replies.size()) +
                     " replies holds a box list (last: " + last_error + ")");
  return out;
}

}  // namespace gslift
