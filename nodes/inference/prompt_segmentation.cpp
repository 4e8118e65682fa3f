#include "nodes/inference/prompt_segmentation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>
#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "nodes/inference/kmeans.hpp"
#include "nodes/inference/mask_silhouette.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {
namespace {

constexpr float kNoQuery = -std::numeric_limits<float>::infinity();

void normalise_rows(float* rows, size_t n, int dim) {
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    float* r = rows + i * dim;
    double s = 0;
    for (int c = 0; c < dim; ++c) s += double(r[c]) * r[c];
    if (s <= 0) return;
    const float inv = static_cast<float>(1.0 / std::sqrt(s));
    for (int c = 0; c < dim; ++c) r[c] *= inv;
  });
}

// max over the queries (q x dim) of <row, query>; kNoQuery without queries.
float best_dot(const float* row, const std::vector<float>& queries, int dim) {
  float best = kNoQuery;
  for (size_t q = 0; q + dim <= queries.size(); q += dim) {
    float d = 0;
    for (int c = 0; c < dim; ++c) d += row[c] * queries[q + c];
    best = std::max(best, d);
  }
  return best;
}

double mean_plus_std(const std::vector<float>& v) {
  double s = 0, s2 = 0;
  for (float x : v) s += x, s2 += double(x) * x;
  const double mean = s / v.size();
  return mean + std::sqrt(std::max(0.0, s2 / v.size() - mean * mean));
}

std::vector<uint32_t> mask_pixels(const cv::Mat1b& mask, bool inside) {
  std::vector<uint32_t> out;
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      if ((mask(y, x) != 0) == inside) out.push_back(static_cast<uint32_t>(y * mask.cols + x));
  return out;
}

// The pixels of polyline strokes through `vertices` (a single vertex is one pixel).
std::vector<uint32_t> stroke_pixels(const std::vector<cv::Point>& vertices, cv::Size size) {
  if (vertices.empty()) return {};
  cv::Mat1b m = cv::Mat1b::zeros(size);
  if (vertices.size() == 1)
    m(vertices[0]) = 255;
  else
    cv::polylines(m, vertices, false, cv::Scalar(255), 1, cv::LINE_8);
  return mask_pixels(m, true);
}

}  // namespace

PromptSegmenter::PromptSegmenter(const GaussianModel& model, const Capture& capture,
                                 const PromptOptions& options)
    : model_(model), capture_(capture), options_(options), dim_(model.feature_dim) {
  prompt_param_table().validate(options_, "inference.prompt");
  if (dim_ < 1 || model.features.size() != model.size() * size_t(dim_) || model.size() == 0)
    throw InputError(
        "inference.prompt: the model has no per-Gaussian features (train them first, e.g. "
        "features.correspondence)");
  unit_ = model.features;
  normalise_rows(unit_.data(), model.size(), dim_);
  maps_.resize(capture.views.size());
}

const UninitVector<float>& PromptSegmenter::feature_map(int v) {
  if (maps_[v].empty()) {
    const View& view = capture_.views[v];
    RenderSettings s;
    s.rgb = false;
    s.features = true;
    maps_[v] = render(model_, view.camera, view.pose, s).features;
    normalise_rows(maps_[v].data(), maps_[v].size() / dim_, dim_);
  }
  return maps_[v];
}

std::vector<float> PromptSegmenter::kmeans_queries(int v, const std::vector<uint32_t>& pixels) {
  if (pixels.empty()) return {};
  return kmeans_of_pixels(feature_map(v).data(), pixels);
}

std::vector<float> PromptSegmenter::kmeans_of_pixels(const float* map,
                                                     const std::vector<uint32_t>& pixels) const {
  if (pixels.empty()) return {};
  const size_t step = (pixels.size() + options_.kmeans_pixels - 1) / options_.kmeans_pixels;
  std::vector<float> rows;
  for (size_t i = 0; i < pixels.size(); i += step)
    rows.insert(rows.end(), map + size_t(pixels[i]) * dim_, map + size_t(pixels[i] + 1) * dim_);
  std::vector<float> q = kmeans(rows, dim_, options_.kmeans_k, options_.seed).centres;
  normalise_rows(q.data(), q.size() / dim_, dim_);
  return q;
}

PromptSelection PromptSegmenter::select_by_queries(const std::vector<float>& positive,
                                                   const std::vector<float>& negative,
                                                   double tau) const {
  const size_t n = model_.size();
  PromptSelection r;
  r.positive_queries = static_cast<int>(positive.size() / dim_);
  r.negative_queries = static_cast<int>(negative.size() / dim_);
  r.score.resize(n);
  std::vector<float> s_n(n);
  tbb::parallel_for(size_t(0), n, [&](size_t g) {
    r.score[g] = best_dot(&unit_[g * dim_], positive, dim_);
    s_n[g] = best_dot(&unit_[g * dim_], negative, dim_);
  });
  if (options_.threshold == PromptThreshold::Fixed) {
    r.threshold = static_cast<float>(tau);
  } else {
    double s = 0;
    for (float x : r.score) s += x;
    r.threshold = static_cast<float>(s / n);
  }
  r.selected.resize(n);
  for (size_t g = 0; g < n; ++g) {
    r.selected[g] = r.score[g] > s_n[g] && r.score[g] > r.threshold;
    r.count += r.selected[g];
  }
  r.positive = positive;
  r.negative = negative;
  return r;
}

cv::Mat1b PromptSegmenter::view_mask(const PromptSelection& r, int v) {
  const Camera& cam = capture_.views[v].camera;
  const UninitVector<float>& map = feature_map(v);
  std::vector<float> s_p(size_t(cam.width) * cam.height), s_n(s_p.size());
  tbb::parallel_for(size_t(0), s_p.size(), [&](size_t px) {
    s_p[px] = best_dot(&map[px * dim_], r.positive, dim_);
    s_n[px] = best_dot(&map[px * dim_], r.negative, dim_);
  });
  const float tau = r.pooled ? static_cast<float>(mean_plus_std(s_p)) : r.threshold;
  cv::Mat1b mask(cam.height, cam.width);
  for (size_t px = 0; px < s_p.size(); ++px)
    mask(static_cast<int>(px / cam.width), static_cast<int>(px % cam.width)) =
        s_p[px] > s_n[px] && s_p[px] > tau ? 255 : 0;
  return mask;
}

PromptSelection PromptSegmenter::select(const Prompt& p) {
  const std::string where = "inference.prompt '" + p.name + "'";
  const int v = capture_.find_view(p.view);
  if (v < 0) throw InputError(where + ": the capture has no view '" + p.view + "'");
  const Camera& cam = capture_.views[v].camera;
  const cv::Size size(cam.width, cam.height);
  const cv::Rect frame(0, 0, cam.width, cam.height);
  for (const auto* list : {&p.positive, &p.negative})
    for (const cv::Point& q : *list)
      if (!frame.contains(q))
        throw InputError(where + ": pixel (" + std::to_string(q.x) + ", " + std::to_string(q.y) +
                         ") lies outside view '" + p.view + "' (" + std::to_string(cam.width) +
                         "x" + std::to_string(cam.height) + ")");
  const bool dense = p.kind == PromptKind::Mask || p.kind == PromptKind::Sam;
  if (dense && (p.mask.size() != size || cv::countNonZero(p.mask) == 0))
    throw InputError(where + ": the mask is empty or not the size of view '" + p.view + "'");
  if (!dense && p.positive.empty()) throw InputError(where + ": no positive pixel");

  if (p.kind == PromptKind::Point) {
    const UninitVector<float>& map = feature_map(v);
    std::vector<float> pos, neg;
    for (const cv::Point& q : p.positive)
      pos.insert(pos.end(), map.begin() + size_t(q.y * cam.width + q.x) * dim_,
                 map.begin() + size_t(q.y * cam.width + q.x + 1) * dim_);
    for (const cv::Point& q : p.negative)
      neg.insert(neg.end(), map.begin() + size_t(q.y * cam.width + q.x) * dim_,
                 map.begin() + size_t(q.y * cam.width + q.x + 1) * dim_);
    return select_by_queries(pos, neg, options_.tau);
  }
  if (p.kind == PromptKind::Scribble)
    return select_by_queries(kmeans_queries(v, stroke_pixels(p.positive, size)),
                             kmeans_queries(v, stroke_pixels(p.negative, size)), options_.tau);

  const std::vector<uint32_t> inside = mask_pixels(p.mask, true);
  if (p.kind == PromptKind::Sam) {
    const UninitVector<float>& map = feature_map(v);
    std::vector<float> q(dim_, 0.f);
    for (uint32_t px : inside)
      for (int c = 0; c < dim_; ++c) q[c] += map[size_t(px) * dim_ + c];
    normalise_rows(q.data(), 1, dim_);
    // The 2D segmentation the pooled query induces in the prompt's own view.
    std::vector<float> pixel_score(size_t(cam.width) * cam.height);
    for (size_t px = 0; px < pixel_score.size(); ++px)
      pixel_score[px] = best_dot(&map[px * dim_], q, dim_);
    const double tau_2d = mean_plus_std(pixel_score);
    size_t covered = 0;
    for (uint32_t px : inside) covered += pixel_score[px] > tau_2d;
    if (covered >= options_.sam_coverage * inside.size()) {
      PromptSelection r = select_by_queries(q, {}, options_.tau);
      r.threshold = static_cast<float>(mean_plus_std(r.score));
      r.count = 0;
      for (size_t g = 0; g < r.score.size(); ++g) {
        r.selected[g] = r.score[g] > r.threshold;
        r.count += r.selected[g];
      }
      r.pooled = true;
      if (options_.mask_validate) validate_by_mask(r, p.mask, capture_.views[v]);
      return r;
    }
  }
  const std::vector<float> neg = options_.mask_negatives
                                     ? kmeans_queries(v, mask_pixels(p.mask, false))
                                     : std::vector<float>{};
  PromptSelection r = select_by_queries(kmeans_queries(v, inside), neg, options_.tau);
  if (options_.mask_validate) validate_by_mask(r, p.mask, capture_.views[v]);
  return r;
}

PromptSelection PromptSegmenter::select_in_camera(const Prompt& p, const Camera& cam,
                                                  const Pose& pose, double tau) {
  const std::string where = "inference.prompt '" + p.name + "'";
  if (p.kind != PromptKind::Point && p.kind != PromptKind::Scribble)
    throw InputError(where + ": only point and scribble prompts can be given in a free camera");
  if (p.positive.empty()) throw InputError(where + ": no positive pixel");
  const cv::Size size(cam.width, cam.height);
  const cv::Rect frame(0, 0, cam.width, cam.height);
  for (const auto* list : {&p.positive, &p.negative})
    for (const cv::Point& q : *list)
      if (!frame.contains(q))
        throw InputError(where + ": pixel (" + std::to_string(q.x) + ", " + std::to_string(q.y) +
                         ") lies outside the " + std::to_string(cam.width) + "x" +
                         std::to_string(cam.height) + " view");
  auto pixels_of = [&](const std::vector<cv::Point>& points) {
    if (p.kind == PromptKind::Scribble) return stroke_pixels(points, size);
    std::vector<uint32_t> out;
    for (const cv::Point& q : points) out.push_back(static_cast<uint32_t>(q.y * cam.width + q.x));
    return out;
  };
  const std::vector<uint32_t> positive = pixels_of(p.positive), negative = pixels_of(p.negative);
  auto rows_at = [&](const std::vector<uint32_t>& pixels) {
    if (p.kind == PromptKind::Scribble) {
      const std::vector<float> rows = features_at(cam, pose, pixels);
      std::vector<uint32_t> all(pixels.size());
      for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<uint32_t>(i);
      return kmeans_of_pixels(rows.data(), all);
    }
    // Points: a window each, so that two clicks far apart do not render the view between them.
    std::vector<float> rows;
    for (uint32_t px : pixels) {
      const std::vector<float> r = features_at(cam, pose, {px});
      rows.insert(rows.end(), r.begin(), r.end());
    }
    return rows;
  };
  return select_by_queries(rows_at(positive), rows_at(negative), tau);
}

std::vector<float> PromptSegmenter::features_at(const Camera& cam, const Pose& pose,
                                                const std::vector<uint32_t>& pixels) const {
  if (pixels.empty()) return {};
  int x0 = cam.width, y0 = cam.height, x1 = -1, y1 = -1;
  for (uint32_t px : pixels) {
    const int x = static_cast<int>(px % cam.width), y = static_cast<int>(px / cam.width);
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  Camera window = cam;
  window.width = x1 - x0 + 1;
  window.height = y1 - y0 + 1;
  window.cx -= x0;
  window.cy -= y0;
  RenderSettings s;
  s.rgb = false;
  s.features = true;
  const UninitVector<float> map = render(model_, window, pose, s).features;
  std::vector<float> rows;
  rows.reserve(pixels.size() * dim_);
  for (uint32_t px : pixels) {
    const size_t at = size_t(px / cam.width - y0) * window.width + (px % cam.width - x0);
    rows.insert(rows.end(), map.begin() + at * dim_, map.begin() + (at + 1) * dim_);
  }
  normalise_rows(rows.data(), pixels.size(), dim_);
  return rows;
}

void PromptSegmenter::validate_by_mask(PromptSelection& r, const cv::Mat1b& mask,
                                       const View& view) const {
  const std::vector<char> outside = centres_outside_mask(model_.means, view, mask);
  for (size_t g = 0; g < r.selected.size(); ++g)
    if (r.selected[g] && outside[g]) {
      r.selected[g] = 0;
      --r.count;
    }
}

std::vector<int32_t> selection_instance_ids(const std::vector<PromptSelection>& selections) {
  const size_t n = selections.empty() ? 0 : selections[0].selected.size();
  std::vector<int32_t> ids(n, -1);
  for (size_t g = 0; g < n; ++g) {
    float best = kNoQuery;
    for (size_t k = 0; k < selections.size(); ++k)
      if (selections[k].selected[g] && selections[k].score[g] > best) {
        best = selections[k].score[g];
        ids[g] = static_cast<int32_t>(k);
      }
  }
  return ids;
}

PromptSet prompt_named(const PromptSet& set, const std::string& name) {
  std::string names;
  for (const Prompt& p : set.prompts) {
    if (p.name == name) {
      PromptSet out;
      out.prompts = {p};
      return out;
    }
    names += (names.empty() ? "'" : ", '") + p.name + "'";
  }
  throw InputError("no prompt is named '" + name +
                   "' (the prompts: " + (names.empty() ? std::string("none") : names) + ")");
}

PromptSet prompts_from_masks(const MaskSet& reference, const std::string& view, PromptKind kind) {
  if (kind == PromptKind::Scribble)
    throw InputError("inference.prompt: scribble prompts come from a prompt file, not from masks");
  const ViewMasks* vm = nullptr;
  for (const ViewMasks& v : reference.views)
    if (v.view == view) vm = &v;
  if (!vm || vm->masks.empty())
    throw InputError("inference.prompt: the reference masks have no mask in view '" + view + "'");
  PromptSet set;
  for (const Mask& m : vm->masks) {
    if (cv::countNonZero(m.pixels) == 0) continue;
    Prompt p;
    p.name = m.label;
    p.kind = kind;
    p.view = view;
    if (kind == PromptKind::Point) {
      const cv::Moments mo = cv::moments(m.pixels, true);
      cv::Point c(static_cast<int>(mo.m10 / mo.m00), static_cast<int>(mo.m01 / mo.m00));
      if (!m.pixels(c)) {
        cv::Mat1f dist;
        cv::Mat1b padded;
        cv::copyMakeBorder(m.pixels, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, 0);
        cv::distanceTransform(padded, dist, cv::DIST_L2, 3);
        cv::minMaxLoc(dist, nullptr, nullptr, nullptr, &c);
        c -= cv::Point(1, 1);
      }
      p.positive.push_back(c);
    } else {
      p.mask = m.pixels;
    }
    set.prompts.push_back(std::move(p));
  }
  return set;
}

const EnumNames<PromptThreshold>& prompt_threshold_names() {
  static const EnumNames<PromptThreshold> names = {{PromptThreshold::Fixed, "fixed"},
                                                   {PromptThreshold::Adaptive, "adaptive"}};
  return names;
}

const ParamTable<PromptOptions>& prompt_param_table() {
  using O = PromptOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("threshold", &O::threshold, prompt_threshold_names(),
               "fixed tau (SAGA code: 0.75) or adaptive (paper: mean positive score)")
          .add("tau", &O::tau, "fixed threshold on the best positive cosine", -1, 1)
          .add("kmeans_k", &O::kmeans_k, "K-means clusters per dense prompt (SAGA: 5)", 1, 64)
          .add("kmeans_pixels", &O::kmeans_pixels,
               "pixels of a dense prompt given to K-means at most (evenly strided)", 1, 1e7)
          .add("sam_coverage", &O::sam_coverage,
               "sam prompts: share of the reference mask the pooled query must cover (SAGA: 0.9)",
               0, 1)
          .add("mask_negatives", &O::mask_negatives,
               "mask / sam prompts: K-means negatives from the pixels outside the mask")
          .add("mask_validate", &O::mask_validate,
               "mask / sam prompts: drop selected Gaussians whose centre projects outside the mask "
               "in the prompt view");
  return table;
}

}  // namespace gslift
