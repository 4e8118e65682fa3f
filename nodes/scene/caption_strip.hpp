// Every picture gslift writes for a person names what it shows (issue 32): a strip under the
// image with a title (what the picture is, what its colours mean) and, for pictures coloured by
// class or instance, a legend of swatches with their names. One place draws it, so every picture
// reads the same; the pixels above the strip are the image as it was.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace gslift {

struct LegendEntry {
  std::string label;
  cv::Vec3b colour;  // RGB, as the pictures are held
};

// The height in pixels of the strip `with_caption` adds for an image `width` wide: a line for the
// title, then as many lines as the legend's swatches need, wrapped at the image's width.
int caption_strip_height(int width, const std::vector<LegendEntry>& legend);

// `rgb` (CV_8UC3, RGB) with a white strip below it: `title` in black, then the legend. Text wider
// than the image is cut at its edge (cv::putText draws what fits).
cv::Mat3b with_caption(const cv::Mat3b& rgb, const std::string& title,
                       const std::vector<LegendEntry>& legend = {});

// Panels of one height side by side, each with its caption above it ("ground truth", "render",
// "instances"), separated by a white gap. Panels of another height are scaled to the first's.
cv::Mat3b side_by_side(const std::vector<std::pair<std::string, cv::Mat3b>>& panels);

}  // namespace gslift
