// The files a text query run leaves behind, so anyone can recompute the metrics from them alone:
// per (view, query) <view>__<query>_mask.png (8-bit, 255 = selected), <view>__<query>_relevancy.png
// (16-bit, relevancy x 65535) and <view>__<query>_overlay.png (the mask tinted red on the view's
// RGB, captioned), plus queries.json naming the selected instances of each query; and per answered
// view with ground truth <view>_gt_render_instances.png: ground truth | render | instances, each
// class in one colour, a legend of class names under them (what `gslift report` shows first).
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "nodes/inference/text_query.hpp"

namespace gslift {

// File-name form of a query: lower case, runs of anything but [a-z0-9] as one '_' ("head
// surgeon" -> "head_surgeon").
std::string query_file_stem(const std::string& query);

// <dir>/<stem>_mask.png (8-bit, 255 = selected) and, when `rgb` (RGB order) has the mask's size,
// <dir>/<stem>_overlay.png: the mask tinted red on the view, captioned with `label` (what was
// asked for). Atomic writes. Shared by every node that leaves masks behind (text queries, prompts).
void write_mask_files(const std::filesystem::path& dir, const std::string& stem,
                      const cv::Mat1b& mask, const cv::Mat& rgb, const std::string& label);

// The name the side-by-side picture of a view ends with; `gslift report` looks for it.
extern const char* const kGtRenderInstancesSuffix;  // "_gt_render_instances.png"

// Ground truth | render | instances of one answered view: the view's ground-truth classes, the
// model's render, and the render with each query's mask in the colour of the class it landed on
// (label_colour of the class id), with a legend of the class names shown. Empty when the view
// has no ground-truth semantics.
cv::Mat3b gt_render_instances(const TextQueryResults& results,
                              const TextQueryResults::ViewAnswers& answers, const View& view,
                              const std::map<int, std::string>& classes, const cv::Mat3b& render);

// Writes the files above into `dir` (atomically). Views are looked up by name in `capture` for
// the overlays (a view without RGB gets none) and rendered from `model` for the side-by-side
// picture.
void write_query_files(const TextQueryResults& results, const Capture& capture,
                       const GaussianModel& model, const std::filesystem::path& dir);

}  // namespace gslift
