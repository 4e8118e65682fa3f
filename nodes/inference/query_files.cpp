#include "nodes/inference/query_files.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "base/atomic_file.hpp"
#include "nodes/scene/image_io.hpp"

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

}  // namespace

void write_mask_files(const std::filesystem::path& dir, const std::string& stem,
                      const cv::Mat1b& mask, const cv::Mat& rgb) {
  write_png(dir / (stem + "_mask.png"), mask);
  if (rgb.size() == mask.size()) write_rgb_png(dir / (stem + "_overlay.png"), overlay(rgb, mask));
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
                       const std::filesystem::path& dir) {
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
      write_mask_files(dir, stem, answers.masks[q], rgb);
      write_png(dir / (stem + "_relevancy.png"), relevancy_png(answers.relevancy[q]));
    }
  }
}

}  // namespace gslift
