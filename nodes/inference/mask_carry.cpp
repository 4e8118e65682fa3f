#include "nodes/inference/mask_carry.hpp"

#include <set>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "nodes/inference/mask_vote_lifting.hpp"
#include "nodes/inference/selection_mask.hpp"

namespace gslift {

namespace {

bool holds_all(const cv::Mat1b& m, const std::vector<cv::Point>& clicks) {
  for (const cv::Point& c : clicks)
    if (!m(c)) return false;
  return !clicks.empty();
}

bool holds_any(const cv::Mat1b& m, const std::vector<cv::Point>& clicks) {
  for (const cv::Point& c : clicks)
    if (m(c)) return true;
  return false;
}

// The 8-connected piece of `m` holding `at` (255 there, 0 elsewhere).
cv::Mat1b piece_at(const cv::Mat1b& m, cv::Point at) {
  cv::Mat1i labels;
  cv::connectedComponents(m, labels, 8, CV_32S);
  return labels == labels(at);
}

// Each click no candidate holds moved to the nearest pixel (Euclidean, first in row order on a
// tie) some candidate holds; unchanged where one holds it or none holds any pixel.
std::vector<cv::Point> snapped_clicks(const std::vector<const cv::Mat1b*>& candidates,
                                      const std::vector<cv::Point>& clicks) {
  std::vector<cv::Point> out = clicks;
  cv::Mat1b held;
  for (cv::Point& c : out) {
    bool is_held = false;
    for (const cv::Mat1b* m : candidates) is_held = is_held || (*m)(c);
    if (is_held || candidates.empty()) continue;
    if (held.empty()) {
      held = cv::Mat1b::zeros(candidates[0]->size());
      for (const cv::Mat1b* m : candidates) held |= *m;
    }
    long best = -1;
    cv::Point at = c;
    for (int y = 0; y < held.rows; ++y)
      for (int x = 0; x < held.cols; ++x) {
        if (!held(y, x)) continue;
        const long d = long(x - c.x) * (x - c.x) + long(y - c.y) * (y - c.y);
        if (best < 0 || d < best) best = d, at = cv::Point(x, y);
      }
    c = at;
  }
  return out;
}

// clicked_mask's rules over masks that hold the clicks; empty (0x0) where none applies.
cv::Mat1b mask_holding(const std::vector<const cv::Mat1b*>& candidates,
                       const std::vector<cv::Point>& clicks, const cv::Mat1b& answer,
                       const std::vector<cv::Point>& others) {
  // Of the masks holding the clicks: those holding no other click, else those holding one too.
  const cv::Mat1b *best = nullptr, *best_merged = nullptr;
  double best_iou = -1, best_merged_iou = -1;
  for (const cv::Mat1b* m : candidates) {
    if (!holds_all(*m, clicks)) continue;
    const double iou = mask_iou(*m, answer);
    if (!holds_any(*m, others)) {
      if (iou > best_iou) best_iou = iou, best = m;
    } else if (iou > best_merged_iou) {
      best_merged_iou = iou, best_merged = m;
    }
  }
  if (best) return best->clone();
  if (best_merged) {
    cv::Mat1b cut = best_merged->clone();
    for (const cv::Mat1b* m : candidates)
      if (holds_any(*m, others) && !holds_any(*m, clicks)) cut &= ~*m;
    if (cut(clicks[0])) {
      cv::Mat1b piece = piece_at(cut, clicks[0]);
      if (holds_all(piece, clicks) && !holds_any(piece, others)) return piece;
    }
  }
  return {};
}

}  // namespace

cv::Mat1b clicked_mask(const std::vector<cv::Mat1b>& candidates,
                       const std::vector<cv::Point>& clicks, const cv::Mat1b& answer,
                       const std::vector<cv::Point>& others) {
  std::vector<const cv::Mat1b*> all;
  bool held = false;
  for (const cv::Mat1b& m : candidates) {
    all.push_back(&m);
    held = held || holds_all(m, clicks);
  }
  cv::Mat1b out = held ? mask_holding(all, clicks, answer, others) : cv::Mat1b();
  if (!out.empty()) return out;
  // The answer's piece under the click: the fallback, and what a gap click's masks must agree with.
  const cv::Mat1b piece = !clicks.empty() && answer(clicks[0])
                              ? piece_at(answer, clicks[0])
                              : cv::Mat1b(cv::Mat1b::zeros(answer.size()));
  if (!held) {
    // SAM answers every click with a mask; its automatic masks leave gaps (thin parts, borders).
    // A click in one is answered as at the nearest pixel of the masks the answer's piece under it
    // covers for half (the features still say which object is meant): where the object has no
    // mask at all, none is near and the answer's piece stays (a neighbour's mask would be next).
    std::vector<const cv::Mat1b*> agreeing;
    for (const cv::Mat1b* m : all) {
      const int area = cv::countNonZero(*m);
      if (area > 0 && 2 * cv::countNonZero(*m & piece) >= area) agreeing.push_back(m);
    }
    out = mask_holding(agreeing, snapped_clicks(agreeing, clicks), answer, others);
  }
  return out.empty() ? piece : out;
}

std::vector<cv::Mat1b> rendered_selections(const PixelRowsView& rows, int width, int height,
                                           const std::vector<std::vector<uint8_t>>& selected,
                                           float threshold) {
  const size_t count = selected.size();
  std::vector<cv::Mat1b> out(count);
  for (cv::Mat1b& m : out) m.create(height, width);
  if (count == 0) return out;
  // Per Gaussian, the selections holding it as bits: a pair visits only those.
  const size_t words = (count + 63) / 64, gaussians = selected[0].size();
  std::vector<uint64_t> held(gaussians * words, 0);
  for (size_t k = 0; k < count; ++k)
    for (size_t g = 0; g < gaussians; ++g)
      if (selected[k][g]) held[g * words + k / 64] |= uint64_t{1} << (k % 64);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& r) {
    std::vector<float> a(count);
    for (int y = r.begin(); y != r.end(); ++y)
      for (int x = 0; x < width; ++x) {
        const size_t p = size_t(y) * width + x;
        std::fill(a.begin(), a.end(), 0.f);
        for (uint32_t e = rows.offsets[p]; e < rows.offsets[p + 1]; ++e)
          for (size_t w = 0; w < words; ++w)
            for (uint64_t bits = held[rows.ids[e] * words + w]; bits != 0; bits &= bits - 1)
              a[w * 64 + __builtin_ctzll(bits)] += rows.weights[e];
        for (size_t k = 0; k < count; ++k) out[k](y, x) = a[k] >= threshold ? 255 : 0;
      }
  });
  return out;
}

cv::Mat1b covered_masks(const std::vector<cv::Mat1b>& candidates, const cv::Mat1b& covered,
                        double coverage) {
  cv::Mat1b out;
  for (const cv::Mat1b& m : candidates) {
    const int area = cv::countNonZero(m);
    if (area == 0 || cv::countNonZero(m & covered) < coverage * area) continue;
    if (out.empty()) out = cv::Mat1b::zeros(m.size());
    out |= m;
  }
  return out;
}

cv::Mat1b containing_masks(const std::vector<cv::Mat1b>& candidates, const cv::Mat1b& own,
                           const std::vector<cv::Mat1b>& others, double containment) {
  cv::Mat1b out;
  const int own_area = cv::countNonZero(own);
  if (own_area == 0) return out;
  std::vector<int> other_area;
  for (const cv::Mat1b& o : others) other_area.push_back(cv::countNonZero(o));
  for (const cv::Mat1b& m : candidates) {
    if (cv::countNonZero(m & own) < containment * own_area) continue;
    bool holds_other = false;
    for (size_t j = 0; j < others.size() && !holds_other; ++j)
      holds_other =
          other_area[j] > 0 && cv::countNonZero(m & others[j]) >= containment * other_area[j];
    if (holds_other) continue;
    if (out.empty()) out = cv::Mat1b::zeros(m.size());
    out |= m;
  }
  return out;
}

cv::Mat1b carried_masks(const std::vector<cv::Mat1b>& candidates, const cv::Mat1b& own,
                        const std::vector<cv::Mat1b>& others, double coverage, double containment) {
  cv::Mat1b out = covered_masks(candidates, own, coverage);
  if (containment <= 0) return out;
  const cv::Mat1b holding = containing_masks(candidates, own, others, containment);
  if (out.empty()) return holding;
  if (!holding.empty()) out |= holding;
  return out;
}

std::vector<size_t> stand_in_masks(const std::vector<cv::Mat1b>& candidates, const cv::Mat1b& own,
                                   const std::vector<cv::Point>& clicks) {
  cv::Mat1b taken = own.clone();
  for (const cv::Mat1b& m : candidates)
    if (holds_any(m, clicks)) taken |= m;
  std::vector<size_t> out;
  for (size_t i = 0; i < candidates.size(); ++i)
    if (cv::countNonZero(candidates[i] & taken) == 0) out.push_back(i);
  return out;
}

std::vector<std::vector<cv::Mat1b>> masks_by_training_view(const Capture& capture,
                                                           const MaskSet& masks) {
  std::vector<std::vector<cv::Mat1b>> out(capture.views.size());
  for (const MaskView& mv : training_mask_views(capture, masks))
    for (const Mask& m : masks.views[mv.mask_view].masks) out[mv.capture_view].push_back(m.pixels);
  return out;
}

std::vector<std::vector<cv::Mat1b>> labelled_masks_by_training_view(
    const Capture& capture, const MaskSet& masks, const std::vector<std::string>& labels) {
  std::vector<std::vector<cv::Mat1b>> out(capture.views.size(),
                                          std::vector<cv::Mat1b>(labels.size()));
  for (const MaskView& mv : training_mask_views(capture, masks)) {
    const ViewMasks& vm = masks.views[mv.mask_view];
    if (vm.masks.empty()) continue;
    const Camera& camera = capture.views[mv.capture_view].camera;
    for (size_t k = 0; k < labels.size(); ++k) {
      cv::Mat1b& union_k = out[mv.capture_view][k];
      union_k = cv::Mat1b::zeros(camera.height, camera.width);
      for (const Mask& m : vm.masks)
        if (m.label == labels[k]) union_k |= m.pixels;
    }
  }
  // A label no training view shows would vote "not the object" everywhere and lift to an empty
  // selection: that is a misnamed prompt or mask file, so say so before any lifting.
  for (size_t k = 0; k < labels.size(); ++k) {
    bool shown = false;
    for (const auto& view : out) shown = shown || (!view[k].empty() && cv::countNonZero(view[k]));
    if (!shown)
      throw InputError("no training view has a mask labelled '" + labels[k] +
                       "' (the labels given are the masks' names; held-out views do not count)");
  }
  return out;
}

std::vector<std::vector<uint8_t>> lift_in_own_views(const GaussianModel& model,
                                                    const Capture& capture,
                                                    const std::vector<int>& view,
                                                    const std::vector<cv::Mat1b>& own,
                                                    double bias) {
  MaskVotes votes(model.size(), own.size());
  for (const int v : std::set<int>(view.begin(), view.end())) {
    std::vector<cv::Mat1b> masks(own.size());
    for (size_t k = 0; k < own.size(); ++k)
      if (view[k] == v) masks[k] = own[k];
    const View& at = capture.views[v];
    const RenderCache weights = render_weights(model, at.camera, at.pose);
    votes.add_view(weights.pixel_rows(), at.camera.width, at.camera.height, masks);
  }
  std::vector<std::vector<uint8_t>> out(own.size());
  for (size_t k = 0; k < own.size(); ++k) out[k] = votes.object(k, bias);
  return out;
}

}  // namespace gslift
