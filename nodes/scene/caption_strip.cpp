#include "nodes/scene/caption_strip.hpp"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"

namespace gslift {

namespace {

// Hershey simplex at 0.4: legible at 1:1 on a 320-pixel view and small beside a 1280-pixel one.
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kScale = 0.4;
constexpr int kLine = 16;    // pixels per text line
constexpr int kMargin = 4;   // left margin and swatch gap
constexpr int kSwatch = 10;  // side of a colour swatch

int text_width(const std::string& text) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, kScale, 1, &baseline).width;
}

// Where each legend entry starts: (line, x), wrapped at `width`.
std::vector<cv::Point> legend_layout(int width, const std::vector<LegendEntry>& legend) {
  std::vector<cv::Point> at;
  int line = 0, x = kMargin;
  for (const auto& e : legend) {
    const int w = kSwatch + kMargin + text_width(e.label) + 2 * kMargin;
    if (x > kMargin && x + w > width) {
      ++line;
      x = kMargin;
    }
    at.push_back({x, line});
    x += w;
  }
  return at;
}

void draw_text(cv::Mat3b& image, const std::string& text, cv::Point origin) {
  cv::putText(image, text, origin, kFont, kScale, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}

}  // namespace

int caption_strip_height(int width, const std::vector<LegendEntry>& legend) {
  if (legend.empty()) return kLine + kMargin;
  return kLine * (2 + legend_layout(width, legend).back().y) + kMargin;
}

cv::Mat3b with_caption(const cv::Mat3b& rgb, const std::string& title,
                       const std::vector<LegendEntry>& legend) {
  if (rgb.empty()) throw InputError("with_caption: empty image for '" + title + "'");
  const int strip = caption_strip_height(rgb.cols, legend);
  cv::Mat3b out(rgb.rows + strip, rgb.cols, cv::Vec3b(255, 255, 255));
  rgb.copyTo(out(cv::Rect(0, 0, rgb.cols, rgb.rows)));
  draw_text(out, title, {kMargin, rgb.rows + kLine - kMargin});
  const std::vector<cv::Point> at = legend_layout(rgb.cols, legend);
  for (size_t k = 0; k < legend.size(); ++k) {
    const int top = rgb.rows + kLine * (1 + at[k].y) + (kLine - kSwatch) / 2;
    const cv::Rect swatch(at[k].x, top, kSwatch, kSwatch);
    cv::rectangle(out, swatch & cv::Rect(0, 0, out.cols, out.rows), legend[k].colour, cv::FILLED);
    cv::rectangle(out, swatch & cv::Rect(0, 0, out.cols, out.rows), cv::Scalar(0, 0, 0), 1);
    draw_text(out, legend[k].label, {at[k].x + kSwatch + kMargin, top + kSwatch - 1});
  }
  return out;
}

cv::Mat3b side_by_side(const std::vector<std::pair<std::string, cv::Mat3b>>& panels) {
  if (panels.empty() || panels[0].second.empty())
    throw InputError("side_by_side: no panels to put side by side");
  const int h = panels[0].second.rows;
  std::vector<cv::Mat3b> scaled;
  int width = 0;
  for (const auto& [caption, image] : panels) {
    cv::Mat3b s = image;
    if (image.rows != h) cv::resize(image, s, {std::max(1, image.cols * h / image.rows), h});
    width += s.cols + (scaled.empty() ? 0 : kMargin);
    scaled.push_back(s);
  }
  cv::Mat3b out(h + kLine + kMargin, width, cv::Vec3b(255, 255, 255));
  int x = 0;
  for (size_t k = 0; k < panels.size(); ++k) {
    draw_text(out, panels[k].first, {x + kMargin, kLine - kMargin});
    scaled[k].copyTo(out(cv::Rect(x, kLine + kMargin, scaled[k].cols, h)));
    x += scaled[k].cols + kMargin;
  }
  return out;
}

}  // namespace gslift
