#include "nodes/inference/query_files.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "base/atomic_file.hpp"
#include "nodes/scene/caption_strip.hpp"
#include "nodes/scene/image_io.hpp"
#include "nodes/scene/label_maps.hpp"
#include "nodes/splat/channel_images.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {
namespace {

void write_png(const std::filesystem::path& path, const cv::Mat& image) {
  write_atomically(path,
                   [&](const std::filesystem::path& tmp) { cv::imwrite(tmp.string(), image); });
}

cv::Mat1w relevancy_png(const cv::Mat1f& relevancy) {
  cv::Mat1w out(relevancy.size());
  for (int y = 0; y < relevancy.rows; ++y)
    for (int x = 0; x < relevancy.cols; ++x)
      out(y, x) =
          static_cast<uint16_t>(std::lround(std::clamp(relevancy(y, x), 0.f, 1.f) * 65535.f));
  return out;
}

// Half-transparent red over the selected pixels (RGB order, as write_rgb_png expects).
cv::Mat overlay(const cv::Mat& rgb, const cv::Mat1b& mask) {
  cv::Mat out = rgb.clone();
  for (int y = 0; y < out.rows; ++y)
    for (int x = 0; x < out.cols; ++x)
      if (mask(y, x)) {
        auto& p = out.at<cv::Vec3b>(y, x);
        p = cv::Vec3b(static_cast<uint8_t>((p[0] + 255) / 2), static_cast<uint8_t>(p[1] / 2),
                      static_cast<uint8_t>(p[2] / 2));
      }
  return out;
}

// Half of `colour` over the pixel.
void tint(cv::Vec3b& p, const cv::Vec3b& colour) {
  for (int k = 0; k < 3; ++k) p[k] = static_cast<uint8_t>((p[k] + colour[k]) / 2);
}

}  // namespace

void write_mask_files(const std::filesystem::path& dir, const std::string& stem,
                      const cv::Mat1b& mask, const cv::Mat& rgb, const std::string& label) {
  write_png(dir / (stem + "_mask.png"), mask);
  if (rgb.size() == mask.size())
    write_rgb_png(dir / (stem + "_overlay.png"),
                  with_caption(overlay(rgb, mask), "'" + label + "' over the view",
                               {{"selected pixels", cv::Vec3b(255, 64, 64)}}));
}

cv::Mat3b gt_render_instances(const TextQueryResults& results,
                              const TextQueryResults::ViewAnswers& answers, const View& view,
                              const std::map<int, std::string>& classes, const cv::Mat3b& render) {
  if (!view.gt_semantic.present()) return {};
  const cv::Mat1i truth = view.gt_semantic.load();
  if (truth.size() != render.size()) return {};
  std::map<std::string, int> class_id;
  for (const auto& [id, name] : classes) class_id[name] = id;
  const cv::Mat3b gt = label_image(truth);
  std::set<int> shown;
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x)
      if (truth(y, x) > 0) shown.insert(truth(y, x));
  cv::Mat3b instances = render.clone();
  for (size_t q = 0; q < answers.masks.size() && q < results.query_classes.size(); ++q) {
    auto it = class_id.find(results.query_classes[q]);
    if (it == class_id.end()) continue;
    shown.insert(it->second);
    const cv::Vec3b colour = label_colour(it->second);
    for (int y = 0; y < instances.rows; ++y)
      for (int x = 0; x < instances.cols; ++x)
        if (answers.masks[q](y, x)) tint(instances(y, x), colour);
  }
  std::vector<LegendEntry> legend;
  for (int id : shown) {
    auto it = classes.find(id);
    legend.push_back(
        {it == classes.end() ? "class " + std::to_string(id) : it->second, label_colour(id)});
  }
  return with_caption(
      side_by_side(
          {{"ground truth", gt}, {"render", render}, {"instances (text queries)", instances}}),
      answers.view + std::string(view.held_out ? " (held out)" : "") +
          ": ground truth | render | instances; black: background",
      legend);
}

std::string query_file_stem(const std::string& query) {
  std::string stem;
  for (char c : query) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u)) {
      stem += static_cast<char>(std::tolower(u));
    } else if (!stem.empty() && stem.back() != '_') {
      stem += '_';
    }
  }
  while (!stem.empty() && stem.back() == '_') stem.pop_back();
  return stem.empty() ? "query" : stem;
}

void write_query_files(const TextQueryResults& results, const Capture& capture,
                       const GaussianModel& model, const std::filesystem::path& dir) {
  nlohmann::json queries = nlohmann::json::array();
  for (size_t q = 0; q < results.queries.size(); ++q) {
    nlohmann::json entry = {{"query", results.queries[q]},
                            {"file_stem", query_file_stem(results.queries[q])},
                            {"instances", results.instances[q]}};
    if (q < results.query_classes.size()) {
      entry["class"] = results.query_classes[q].empty() ? nlohmann::json(nullptr)
                                                        : nlohmann::json(results.query_classes[q]);
      entry["class_score"] = results.query_class_scores[q];
    }
    queries.push_back(std::move(entry));
  }
  write_file_atomically(dir / "queries.json", queries.dump(2) + "\n");
  for (const auto& answers : results.views) {
    const int vi = capture.find_view(answers.view);
    const cv::Mat rgb =
        vi >= 0 && capture.views[vi].rgb.present() ? capture.views[vi].rgb.load() : cv::Mat();
    for (size_t q = 0; q < results.queries.size(); ++q) {
      const std::string stem = answers.view + "__" + query_file_stem(results.queries[q]);
      write_mask_files(dir, stem, answers.masks[q], rgb, results.queries[q]);
      write_png(dir / (stem + "_relevancy.png"), relevancy_png(answers.relevancy[q]));
    }
    if (vi < 0 || !capture.views[vi].gt_semantic.present()) continue;
    const View& view = capture.views[vi];
    const cv::Mat3b render_rgb =
        channel_image(render(model, view.camera, view.pose, RenderSettings{}), "rgb");
    const cv::Mat3b picture =
        gt_render_instances(results, answers, view, capture.classes, render_rgb);
    if (!picture.empty()) write_rgb_png(dir / (answers.view + kGtRenderInstancesSuffix), picture);
  }
}

}  // namespace gslift
