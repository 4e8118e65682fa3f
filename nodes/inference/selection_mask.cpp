#include "nodes/inference/selection_mask.hpp"

#include <algorithm>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "base/errors.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {
namespace {

constexpr int kTile = 16;  // 256 pixels: a pixel's place in its tile fits in a byte

struct Pair {
  uint32_t id;
  uint8_t pixel;
  float weight;
};

}  // namespace

RenderCache render_weights(const GaussianModel& model, const Camera& camera, const Pose& pose) {
  RenderSettings weights_only;
  weights_only.rgb = false;
  weights_only.alpha = true;
  return RenderCache(render(model, camera, pose, weights_only));
}

SelectionMasker::SelectionMasker(const GaussianModel& model, const Camera& camera, const Pose& pose)
    : SelectionMasker(render_weights(model, camera, pose)) {}

SelectionMasker::SelectionMasker(const RenderCache& cache)
    : width_(cache.width()),
      height_(cache.height()),
      tiles_x_((cache.width() + kTile - 1) / kTile),
      tiles_y_((cache.height() + kTile - 1) / kTile),
      gaussians_(cache.gaussian_count()) {
  const auto& off = cache.pixel_offsets();
  const auto& ids = cache.ids();
  const auto& w = cache.weights();
  const int tiles = tiles_x_ * tiles_y_;
  auto tile_rect = [&](int t) {
    const int x0 = (t % tiles_x_) * kTile, y0 = (t / tiles_x_) * kTile;
    return cv::Rect(x0, y0, std::min(kTile, width_ - x0), std::min(kTile, height_ - y0));
  };
  // Pairs per tile, and where each tile's pairs start.
  std::vector<uint32_t> pair_begin(size_t(tiles) + 1, 0);
  for (int t = 0; t < tiles; ++t) {
    const cv::Rect r = tile_rect(t);
    uint32_t n = 0;
    for (int y = r.y; y < r.y + r.height; ++y)
      n += off[size_t(y) * width_ + r.x + r.width] - off[size_t(y) * width_ + r.x];
    pair_begin[t + 1] = pair_begin[t] + n;
  }
  pair_pixels_.resize(pair_begin[tiles]);
  pair_weights_.resize(pair_begin[tiles]);
  // Per tile: its Gaussians (ascending) and their pair counts, concatenated below.
  std::vector<std::vector<uint32_t>> tile_ids(tiles), tile_counts(tiles);
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles), [&](const tbb::blocked_range<int>& range) {
    std::vector<Pair> pairs;
    for (int t = range.begin(); t != range.end(); ++t) {
      const cv::Rect r = tile_rect(t);
      pairs.clear();
      for (int y = r.y; y < r.y + r.height; ++y)
        for (int x = r.x; x < r.x + r.width; ++x) {
          const size_t p = size_t(y) * width_ + x;
          const uint8_t local = static_cast<uint8_t>((y - r.y) * kTile + (x - r.x));
          for (uint32_t e = off[p]; e < off[p + 1]; ++e) pairs.push_back({ids[e], local, w[e]});
        }
      // Gathered in ascending pixel order: the stable sort keeps it within each Gaussian.
      std::stable_sort(pairs.begin(), pairs.end(),
                       [](const Pair& a, const Pair& b) { return a.id < b.id; });
      for (size_t k = 0; k < pairs.size(); ++k) {
        pair_pixels_[pair_begin[t] + k] = pairs[k].pixel;
        pair_weights_[pair_begin[t] + k] = pairs[k].weight;
        if (k == 0 || pairs[k].id != pairs[k - 1].id) {
          tile_ids[t].push_back(pairs[k].id);
          tile_counts[t].push_back(0);
        }
        ++tile_counts[t].back();
      }
    }
  });
  tile_offsets_.assign(size_t(tiles) + 1, 0);
  for (int t = 0; t < tiles; ++t)
    tile_offsets_[t + 1] = tile_offsets_[t] + static_cast<uint32_t>(tile_ids[t].size());
  entry_ids_.reserve(tile_offsets_[tiles]);
  entry_offsets_.reserve(size_t(tile_offsets_[tiles]) + 1);
  for (int t = 0; t < tiles; ++t) {
    uint32_t at = pair_begin[t];
    for (size_t k = 0; k < tile_ids[t].size(); ++k) {
      entry_ids_.push_back(tile_ids[t][k]);
      entry_offsets_.push_back(at);
      at += tile_counts[t][k];
    }
  }
  entry_offsets_.push_back(pair_begin[tiles]);
}

size_t SelectionMasker::bytes() const {
  return sizeof(uint32_t) * (tile_offsets_.size() + entry_ids_.size() + entry_offsets_.size()) +
         pair_pixels_.size() * (sizeof(uint8_t) + sizeof(float));
}

template <class Write>
void SelectionMasker::accumulate(const std::vector<uint8_t>& selected, Write&& write) const {
  if (selected.size() != gaussians_)
    throw InputError("selection mask: " + std::to_string(selected.size()) +
                     " flags for a model of " + std::to_string(gaussians_) + " Gaussians");
  const int tiles = tiles_x_ * tiles_y_;
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 8), [&](const tbb::blocked_range<int>& r) {
    float acc[kTile * kTile];
    for (int t = r.begin(); t != r.end(); ++t) {
      std::fill(acc, acc + kTile * kTile, 0.f);
      for (uint32_t e = tile_offsets_[t]; e < tile_offsets_[t + 1]; ++e) {
        if (!selected[entry_ids_[e]]) continue;
        for (uint32_t k = entry_offsets_[e]; k < entry_offsets_[e + 1]; ++k)
          acc[pair_pixels_[k]] += pair_weights_[k];
      }
      const int x0 = (t % tiles_x_) * kTile, y0 = (t / tiles_x_) * kTile;
      const int w = std::min(kTile, width_ - x0), h = std::min(kTile, height_ - y0);
      for (int y = 0; y < h; ++y) write(y0 + y, x0, acc + y * kTile, w);
    }
  });
}

cv::Mat1f SelectionMasker::coverage(const std::vector<uint8_t>& selected) const {
  cv::Mat1f out(height_, width_);
  accumulate(selected, [&](int y, int x0, const float* row, int w) {
    std::copy(row, row + w, out.ptr<float>(y) + x0);
  });
  return out;
}

cv::Mat1b SelectionMasker::mask(const std::vector<uint8_t>& selected, float threshold) const {
  cv::Mat1b out(height_, width_);
  accumulate(selected, [&](int y, int x0, const float* row, int w) {
    uint8_t* px = out.ptr<uint8_t>(y) + x0;
    for (int x = 0; x < w; ++x) px[x] = row[x] >= threshold ? 255 : 0;
  });
  return out;
}

}  // namespace gslift
