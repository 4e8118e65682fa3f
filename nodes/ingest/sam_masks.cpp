#include "nodes/ingest/sam_masks.hpp"

#include <map>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "base/json_read.hpp"
#include "nodes/ingest/coco_rle.hpp"

namespace gslift {
namespace {

using nlohmann::json;

json parse_list(const std::string& text, const std::string& where) {
  json j;
  try {
    j = parse_json(text);
  } catch (const json::exception& e) {
    throw InputError(where + ": invalid JSON: " + e.what());
  }
  if (!j.is_array()) throw InputError(where + ": expected a JSON list of masks");
  return j;
}

float number_or(const json& record, const char* key, float fallback, const std::string& where) {
  if (!record.contains(key)) return fallback;
  if (!record[key].is_number()) throw InputError(where + ": '" + key + "' must be a number");
  return record[key].get<float>();
}

}  // namespace

json sam_mask_record(const cv::Mat1b& mask, double predicted_iou, double stability) {
  const cv::Rect b = cv::boundingRect(mask);
  const json rle = {{"size", {mask.rows, mask.cols}},
                    {"counts", rle_counts_to_string(rle_encode(mask))}};
  return {{"segmentation", rle},
          {"bbox", {b.x, b.y, b.width, b.height}},
          {"area", cv::countNonZero(mask)},
          {"predicted_iou", predicted_iou},
          {"stability_score", stability}};
}

std::vector<Mask> parse_sam_auto_masks(const std::string& json_text, const std::string& where) {
  const json list = parse_list(json_text, where);
  std::vector<Mask> masks;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string item = where + " mask " + std::to_string(i);
    const json& r = list[i];
    if (!r.is_object() || !r.contains("segmentation"))
      throw InputError(item + ": expected a record with 'segmentation'");
    Mask m;
    m.pixels = rle_decode_json(r["segmentation"], item);
    m.score = number_or(r, "predicted_iou", 1.f, item);
    m.granularity = static_cast<int>(number_or(r, "granularity", 0.f, item));
    masks.push_back(std::move(m));
  }
  return masks;
}

std::vector<std::optional<Mask>> parse_sam_box_masks(const std::string& json_text,
                                                     const std::string& where) {
  const json list = parse_list(json_text, where);
  std::vector<std::optional<Mask>> masks;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string item = where + " mask " + std::to_string(i);
    const json& r = list[i];
    if (r.is_null()) {
      masks.emplace_back();
      continue;
    }
    Mask m;
    const bool record = r.is_object() && r.contains("segmentation");
    m.pixels = rle_decode_json(record ? r["segmentation"] : r, item);
    if (record) m.score = number_or(r, "score", number_or(r, "predicted_iou", 1.f, item), item);
    m.box_index = static_cast<int>(i);
    masks.emplace_back(std::move(m));
  }
  return masks;
}

std::vector<Mask> masks_from_instance_map(const cv::Mat& ids) {
  CV_Assert(ids.type() == CV_32SC1);
  std::map<int, cv::Mat1b> by_id;
  for (int y = 0; y < ids.rows; ++y)
    for (int x = 0; x < ids.cols; ++x) {
      const int id = ids.at<int>(y, x);
      if (id == 0) continue;
      auto it = by_id.find(id);
      if (it == by_id.end()) it = by_id.emplace(id, cv::Mat1b(ids.size(), uchar(0))).first;
      it->second(y, x) = 255;
    }
  std::vector<Mask> masks;
  for (auto& [id, pixels] : by_id) {
    Mask m;
    m.pixels = pixels;
    m.label = std::to_string(id);
    masks.push_back(std::move(m));
  }
  return masks;
}

}  // namespace gslift
