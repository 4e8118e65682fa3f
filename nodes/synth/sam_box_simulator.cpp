#include "nodes/synth/sam_box_simulator.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <opencv2/imgproc.hpp>

#include "nodes/synth/mask_boundary_noise.hpp"

namespace gslift::synth {

namespace {

// The box in whole pixels, clipped to the image; may be empty.
cv::Rect pixel_rect(const Box& b, int width, int height) {
  const int x1 = std::max(0, static_cast<int>(std::floor(b.x1)));
  const int y1 = std::max(0, static_cast<int>(std::floor(b.y1)));
  const int x2 = std::min(width, static_cast<int>(std::ceil(b.x2)));
  const int y2 = std::min(height, static_cast<int>(std::ceil(b.y2)));
  return cv::Rect(x1, y1, std::max(0, x2 - x1), std::max(0, y2 - y1));
}

// Pixels of `id` inside `r`.
cv::Mat1b region(const cv::Mat& ids, int id, const cv::Rect& r) {
  cv::Mat1b m(ids.size(), uchar(0));
  for (int y = r.y; y < r.y + r.height; ++y) {
    const int* row = ids.ptr<int>(y);
    for (int x = r.x; x < r.x + r.width; ++x) {
      if (row[x] == id) m(y, x) = 255;
    }
  }
  return m;
}

}  // namespace

std::vector<int> count_labels(const cv::Mat& ids, const cv::Rect& r) {
  double max_id = 0;
  cv::minMaxLoc(ids, nullptr, &max_id);
  std::vector<int> counts(static_cast<size_t>(max_id) + 1, 0);
  for (int y = r.y; y < r.y + r.height; ++y) {
    const int* row = ids.ptr<int>(y);
    for (int x = r.x; x < r.x + r.width; ++x) ++counts[row[x]];
  }
  return counts;
}

SamBoxMask simulate_sam_box(const Box& box, const cv::Mat& instance_map,
                            const std::vector<int>& instance_pixels, const SynthKnobs& knobs,
                            RandomStream& rng) {
  const int width = instance_map.cols, height = instance_map.rows;
  SamBoxMask out;
  const cv::Rect r = pixel_rect(box, width, height);
  if (r.area() == 0) {
    out.mask = cv::Mat1b(instance_map.size(), uchar(0));
    return out;
  }
  const std::vector<int> inside = count_labels(instance_map, r);
  double best = kMinBoxCoverage;
  for (size_t id = 1; id < inside.size(); ++id) {
    const double n = inside[id];
    if (n == 0) continue;
    const double score = n * n / (double(instance_pixels.at(id)) * r.area());
    if (score >= best) best = score, out.instance = static_cast<int>(id);
  }

  if (out.instance == 0) {
    // Wrong blob: an ellipse inside the box restricted to the region that dominates the box
    // (floor, wall or a sliver of an object), as SAM segments whatever is under the prompt.
    const int dominant =
        static_cast<int>(std::max_element(inside.begin(), inside.end()) - inside.begin());
    cv::Mat1b blob(instance_map.size(), uchar(0));
    const cv::Point centre(r.x + static_cast<int>(rng.uniform(0.3, 0.7) * r.width),
                           r.y + static_cast<int>(rng.uniform(0.3, 0.7) * r.height));
    const cv::Size axes(std::max(1, static_cast<int>(rng.uniform(0.15, 0.45) * r.width)),
                        std::max(1, static_cast<int>(rng.uniform(0.15, 0.45) * r.height)));
    cv::ellipse(blob, centre, axes, 0, 0, 360, cv::Scalar(255), cv::FILLED);
    cv::Mat1b restricted = blob & region(instance_map, dominant, r);
    out.mask = perturb_mask_boundary(cv::countNonZero(restricted) >= 20 ? restricted : blob,
                                     knobs.sam_boundary_noise, rng);
    return out;
  }

  // SAM's box-prompted mask stays near the box: the instance's pixels in the box grown by 10%.
  const cv::Rect grown = cv::Rect(r.x - r.width / 10, r.y - r.height / 10, r.width + r.width / 5,
                                  r.height + r.height / 5) &
                         cv::Rect(0, 0, width, height);
  cv::Mat1b mask = region(instance_map, out.instance, grown);
  if (rng.chance(knobs.sam_leak_rate)) {
    // Leak into the neighbour that shares the longest border with the mask inside the box.
    cv::Mat1b ring;
    cv::dilate(mask, ring, cv::Mat(), cv::Point(-1, -1), 2);
    std::map<int, int> border;
    for (int y = r.y; y < r.y + r.height; ++y) {
      for (int x = r.x; x < r.x + r.width; ++x) {
        const int id = instance_map.at<int>(y, x);
        if (ring(y, x) && id != 0 && id != out.instance) ++border[id];
      }
    }
    int most = 0;
    for (const auto& [id, n] : border) {
      if (n > most) most = n, out.leaked_into = id;
    }
    if (out.leaked_into != 0) mask |= region(instance_map, out.leaked_into, r);
  }
  out.mask = perturb_mask_boundary(mask, knobs.sam_boundary_noise, rng);
  return out;
}

}  // namespace gslift::synth
