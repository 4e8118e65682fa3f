#include "nodes/synth/sam_auto_simulator.hpp"

#include <algorithm>
#include <map>
#include <set>

#include <opencv2/imgproc.hpp>

#include "nodes/synth/mask_boundary_noise.hpp"

namespace gslift::synth {

namespace {

// Shared border length (4-neighbour pixel pairs) between every pair of distinct instances.
std::map<std::pair<int, int>, int> adjacency(const cv::Mat& ids) {
  std::map<std::pair<int, int>, int> border;
  auto add = [&](int a, int b) {
    if (a == b || a == 0 || b == 0) return;
    ++border[{std::min(a, b), std::max(a, b)}];
  };
  for (int y = 0; y < ids.rows; ++y) {
    for (int x = 0; x < ids.cols; ++x) {
      if (x + 1 < ids.cols) add(ids.at<int>(y, x), ids.at<int>(y, x + 1));
      if (y + 1 < ids.rows) add(ids.at<int>(y, x), ids.at<int>(y + 1, x));
    }
  }
  return border;
}

}  // namespace

std::vector<AutoMask> simulate_sam_auto(const cv::Mat& instance_map, const cv::Mat& part_map,
                                        const SynthKnobs& knobs, RandomStream& rng,
                                        double min_area_fraction) {
  const int min_area =
      std::max(1, static_cast<int>(min_area_fraction * instance_map.rows * instance_map.cols));
  // Visible pixel count of every instance and of every (instance, part).
  std::map<int, int> pixels;
  std::map<int, std::map<int, int>> part_pixels;
  for (int y = 0; y < instance_map.rows; ++y) {
    for (int x = 0; x < instance_map.cols; ++x) {
      const int id = instance_map.at<int>(y, x);
      if (id == 0) continue;
      ++pixels[id];
      ++part_pixels[id][part_map.at<int>(y, x)];
    }
  }
  auto visible_parts = [&](int id) {
    std::vector<int> parts;
    for (const auto& [p, n] : part_pixels[id]) {
      if (n >= min_area) parts.push_back(p);
    }
    return parts;
  };
  auto instance_mask = [&](int id, int part) {
    cv::Mat1b m = instance_map == id;
    if (part >= 0) m &= part_map == part;
    return m;
  };
  const auto border = adjacency(instance_map);

  std::vector<AutoMask> out;
  auto push = [&](cv::Mat1b mask, AutoMask::Kind kind, int granularity, std::vector<int> ids) {
    AutoMask a;
    a.mask = perturb_mask_boundary(mask, knobs.sam_boundary_noise, rng);
    a.kind = kind;
    a.granularity = granularity;
    a.instances = std::move(ids);
    a.predicted_iou = static_cast<float>(rng.uniform(0.9, 1.0));
    a.stability_score = static_cast<float>(rng.uniform(0.95, 1.0));
    if (cv::countNonZero(a.mask) >= min_area) out.push_back(std::move(a));
  };

  std::set<int> done;
  for (const auto& [id, n] : pixels) {
    if (n < min_area || done.count(id)) continue;
    done.insert(id);
    const double u = rng.uniform();
    if (u < knobs.sam_auto_merge_rate) {
      // Merge with the not-yet-used neighbour sharing the longest border, if there is one.
      int partner = 0, longest = 0;
      for (const auto& [pair, len] : border) {
        const int other = pair.first == id ? pair.second : (pair.second == id ? pair.first : 0);
        if (other != 0 && !done.count(other) && pixels[other] >= min_area && len > longest) {
          longest = len, partner = other;
        }
      }
      if (partner != 0) {
        done.insert(partner);
        push(instance_mask(id, -1) | instance_mask(partner, -1), AutoMask::Kind::Merged, 0,
             {id, partner});
        continue;
      }
    }
    const std::vector<int> parts = visible_parts(id);
    if (u >= knobs.sam_auto_merge_rate &&
        u < knobs.sam_auto_merge_rate + knobs.sam_auto_split_rate && parts.size() >= 2) {
      for (int p : parts) push(instance_mask(id, p), AutoMask::Kind::Part, 0, {id});
      continue;
    }
    push(instance_mask(id, -1), AutoMask::Kind::Whole, 0, {id});
  }

  if (knobs.sam_auto_granularities >= 2) {
    for (const auto& [id, n] : pixels) {
      if (n < min_area) continue;
      const std::vector<int> parts = visible_parts(id);
      if (parts.size() < 2) continue;
      for (int p : parts) push(instance_mask(id, p), AutoMask::Kind::Part, 1, {id});
    }
  }

  // Spurious fragments: small blobs of whatever region lies under a random point (a shadow, a
  // tile, a fold), the typical leftovers of a point-grid prompt.
  const int fragments = rng.poisson(knobs.sam_auto_fragments);
  const int scale = std::max(4, std::min(instance_map.cols, instance_map.rows) / 20);
  for (int f = 0; f < fragments; ++f) {
    const cv::Point c(rng.below(instance_map.cols), rng.below(instance_map.rows));
    cv::Mat1b blob(instance_map.size(), uchar(0));
    cv::ellipse(blob, c, cv::Size(scale / 2 + rng.below(scale), scale / 2 + rng.below(scale)),
                rng.uniform(0, 180), 0, 360, cv::Scalar(255), cv::FILLED);
    blob &= instance_map == instance_map.at<int>(c);
    // Fragments are judged by their own size, not min_area: small is what makes them spurious.
    AutoMask a;
    a.mask = blob;
    a.kind = AutoMask::Kind::Fragment;
    a.predicted_iou = static_cast<float>(rng.uniform(0.88, 0.92));
    a.stability_score = static_cast<float>(rng.uniform(0.95, 0.97));
    if (cv::countNonZero(blob) > 0) out.push_back(std::move(a));
  }
  return out;
}

}  // namespace gslift::synth
