#include "nodes/splat/channel_images.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace gslift {
namespace {

// Min-max normalises channel c of an interleaved image with `stride` floats per pixel into an
// 8-bit grey plane; pixels where `valid` is false stay black.
template <class Values, class Valid>
cv::Mat normalised_plane(const Values& data, int rows, int cols, int stride, int c, Valid valid) {
  float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
  for (int p = 0; p < rows * cols; ++p)
    if (valid(p)) lo = std::min(lo, data[p * stride + c]), hi = std::max(hi, data[p * stride + c]);
  cv::Mat plane = cv::Mat::zeros(rows, cols, CV_8UC1);
  const float range = hi > lo ? hi - lo : 1.f;
  for (int p = 0; p < rows * cols; ++p)
    if (valid(p))
      plane.at<uint8_t>(p) =
          cv::saturate_cast<uint8_t>(255.f * (data[p * stride + c] - lo) / range);
  return plane;
}

cv::Mat grey_to_rgb(const cv::Mat& plane) {
  cv::Mat out;
  cv::merge(std::vector<cv::Mat>{plane, plane, plane}, out);
  return out;
}

template <class Values>
void require(const Values& data, size_t size, const std::string& channel) {
  if (data.size() != size)
    throw std::invalid_argument("channel '" + channel + "' was not rendered");
}

}  // namespace

const std::vector<std::string>& image_channels() {
  static const std::vector<std::string> kChannels = {"rgb", "depth", "normal", "alpha", "features"};
  return kChannels;
}

void request_channel(RenderSettings& s, const std::string& channel) {
  if (channel == "rgb")
    s.rgb = true;
  else if (channel == "depth")
    s.depth = true;
  else if (channel == "normal")
    s.normal = true;
  else if (channel == "alpha")
    s.alpha = true;
  else if (channel == "features")
    s.features = true;
  else
    throw std::invalid_argument("unknown render channel '" + channel + "'");
}

cv::Mat channel_image(const RenderOutput& out, const std::string& channel) {
  const int rows = out.height, cols = out.width;
  const size_t pixels = static_cast<size_t>(rows) * cols;
  cv::Mat image(rows, cols, CV_8UC3, cv::Scalar::all(0));
  if (channel == "rgb") {
    require(out.rgb, pixels * 3, channel);
    for (size_t i = 0; i < pixels * 3; ++i)
      image.data[i] = cv::saturate_cast<uint8_t>(255.f * std::clamp(out.rgb[i], 0.f, 1.f));
  } else if (channel == "depth") {
    require(out.depth, pixels, channel);
    return grey_to_rgb(
        normalised_plane(out.depth, rows, cols, 1, 0, [&](int p) { return out.depth[p] > 0; }));
  } else if (channel == "normal") {
    require(out.normal, pixels * 3, channel);
    for (size_t p = 0; p < pixels; ++p) {
      const float* n = &out.normal[p * 3];
      const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (len < 1e-6f) continue;
      for (int c = 0; c < 3; ++c)
        image.data[p * 3 + c] = cv::saturate_cast<uint8_t>(127.5f * (n[c] / len + 1));
    }
  } else if (channel == "alpha") {
    require(out.alpha, pixels, channel);
    for (size_t p = 0; p < pixels; ++p)
      for (int c = 0; c < 3; ++c)
        image.data[p * 3 + c] = cv::saturate_cast<uint8_t>(255.f * out.alpha[p]);
  } else if (channel == "features") {
    const int d = out.feature_dim;
    if (d == 0) return image;
    require(out.features, pixels * d, channel);
    std::vector<cv::Mat> planes;
    for (int c = 0; c < 3; ++c)
      planes.push_back(normalised_plane(out.features, rows, cols, d, std::min(c, d - 1),
                                        [](int) { return true; }));
    cv::merge(planes, image);
  } else {
    throw std::invalid_argument("unknown render channel '" + channel + "'");
  }
  return image;
}

std::string channel_meaning(const std::string& channel) {
  if (channel == "rgb") return "the rendered colour";
  if (channel == "depth") return "grey, black nearest to white farthest; black: no depth";
  if (channel == "normal") return "world normal (n + 1) / 2 as RGB (x red, y green, z blue)";
  if (channel == "alpha") return "accumulated opacity, black 0 to white 1";
  if (channel == "features") return "first three feature channels as RGB, each min-max scaled";
  throw std::invalid_argument("unknown render channel '" + channel + "'");
}

}  // namespace gslift
