// The files a text query run leaves behind, so anyone can recompute the metrics from them alone:
// per (view, query) <view>__<query>_mask.png (8-bit, 255 = selected), <view>__<query>_relevancy.png
// (16-bit, relevancy x 65535) and <view>__<query>_overlay.png (the mask tinted red on the view's
// RGB), plus queries.json naming the selected instances of each query.
#pragma once

#include <filesystem>
#include <string>

#include "nodes/inference/text_query.hpp"

namespace gslift {

// File-name form of a query: lower case, runs of anything but [a-z0-9] as one '_' ("head
// surgeon" -> "head_surgeon").
std::string query_file_stem(const std::string& query);

// <dir>/<stem>_mask.png (8-bit, 255 = selected) and, when `rgb` (RGB order) has the mask's size,
// <dir>/<stem>_overlay.png: the mask tinted red on the view. Atomic writes. Shared by every node
// that leaves masks behind (text queries, prompts).
void write_mask_files(const std::filesystem::path& dir, const std::string& stem,
                      const cv::Mat1b& mask, const cv::Mat& rgb);

// Writes the files above into `dir` (atomically). Views are looked up by name in `capture` for
// the overlays; a view without RGB gets no overlay.
void write_query_files(const TextQueryResults& results, const Capture& capture,
                       const std::filesystem::path& dir);

}  // namespace gslift
