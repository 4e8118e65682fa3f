#include "nodes/splat/view_geometry.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "base/errors.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/reconstruct.hpp"
#include "nodes/splat/render_cache.hpp"

namespace gslift {
namespace {

// The picture's colours (RGB): floaters red, holes blue; surfaces no training view saw are the
// render greyed to a third over mid grey.
const cv::Vec3b kFloaterColour(255, 0, 0);
const cv::Vec3b kHoleColour(0, 64, 255);

cv::Mat1f ground_truth_depth(const View& v) {
  const cv::Mat d = v.gt_depth.load();
  if (d.empty() || d.type() != CV_32FC1 || d.cols != v.camera.width || d.rows != v.camera.height)
    throw InputError("view '" + v.name + "' has no ground-truth depth of its camera size");
  return d;
}

double ratio(double num, double den) {
  return den > 0 ? num / den : ViewGeometry::kNone;
}

}  // namespace

std::vector<float> median_depth(const GaussianModel& model, const Pose& pose,
                                const RenderOutput& forward) {
  const RenderCache cache(forward);
  std::vector<float> z(model.size());
  for (size_t i = 0; i < z.size(); ++i)
    z[i] = static_cast<float>(
        pose.to_camera(
                Eigen::Vector3d(model.means[i * 3], model.means[i * 3 + 1], model.means[i * 3 + 2]))
            .z());
  const auto& offsets = cache.pixel_offsets();
  const auto& ids = cache.ids();
  const auto& weights = cache.weights();
  std::vector<float> depth(offsets.size() - 1, 0.f);
  tbb::parallel_for(size_t(0), depth.size(), [&](size_t p) {
    float sum = 0;
    for (uint32_t k = offsets[p]; k < offsets[p + 1]; ++k) {
      sum += weights[k];  // front to back: the weights so far are 1 - T
      if (sum >= 0.5f) {
        depth[p] = z[ids[k]];
        break;
      }
    }
  });
  return depth;
}

cv::Mat1b depth_discontinuities(const cv::Mat1f& depth, double jump, int radius) {
  cv::Mat1b edge(depth.size(), uchar(0));
  const auto split = [&](float a, float b) {
    if (!(a > 0) && !(b > 0)) return false;
    if (!(a > 0) || !(b > 0)) return true;
    return std::abs(a - b) > jump * std::min(a, b);
  };
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x) {
      if (x + 1 < depth.cols && split(depth(y, x), depth(y, x + 1)))
        edge(y, x) = edge(y, x + 1) = 1;
      if (y + 1 < depth.rows && split(depth(y, x), depth(y + 1, x)))
        edge(y, x) = edge(y + 1, x) = 1;
    }
  cv::Mat1b near(depth.size(), uchar(0));
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x) {
      if (!edge(y, x)) continue;
      for (int v = std::max(0, y - radius); v <= std::min(depth.rows - 1, y + radius); ++v)
        for (int u = std::max(0, x - radius); u <= std::min(depth.cols - 1, x + radius); ++u)
          near(v, u) = 1;
    }
  return near;
}

cv::Mat1b covered_pixels(const Capture& capture, int view, const std::vector<int>& train,
                         double tolerance) {
  const View& ref = capture.views[view];
  const cv::Mat1f depth = ground_truth_depth(ref);
  std::vector<cv::Mat1f> train_depth;
  for (const int t : train) train_depth.push_back(ground_truth_depth(capture.views[t]));
  const Camera& c = ref.camera;
  cv::Mat1b covered(depth.size(), uchar(0));
  tbb::parallel_for(0, depth.rows, [&](int y) {
    for (int x = 0; x < depth.cols; ++x) {
      const float d = depth(y, x);
      if (!(d > 0)) continue;
      const Eigen::Vector3d cam((x + 0.5 - c.cx) / c.fx * d, (y + 0.5 - c.cy) / c.fy * d, d);
      const Eigen::Vector3d world = ref.pose.R.transpose() * (cam - ref.pose.t);
      for (size_t k = 0; k < train.size(); ++k) {
        const View& tv = capture.views[train[k]];
        const Eigen::Vector3d p = tv.pose.to_camera(world);
        if (p.z() <= 0) continue;
        const double u = tv.camera.fx * p.x() / p.z() + tv.camera.cx;
        const double v = tv.camera.fy * p.y() / p.z() + tv.camera.cy;
        const int iu = static_cast<int>(std::floor(u)), iv = static_cast<int>(std::floor(v));
        if (iu < 0 || iv < 0 || iu >= tv.camera.width || iv >= tv.camera.height) continue;
        const float seen = train_depth[k](iv, iu);
        if (seen > 0 && std::abs(seen - p.z()) <= tolerance * p.z()) {
          covered(y, x) = 1;
          break;
        }
      }
    }
  });
  return covered;
}

ViewGeometry view_geometry(const GaussianModel& model, const Capture& capture, int view,
                           const std::vector<int>& train, const Eigen::Vector3f& background,
                           cv::Mat3b* picture) {
  const View& v = capture.views[view];
  const cv::Mat1f truth = ground_truth_depth(v);
  const cv::Mat1b covered = covered_pixels(capture, view, train);
  const cv::Mat1b discontinuity = depth_discontinuities(truth);
  RenderSettings settings;
  settings.depth = true;
  settings.alpha = true;
  settings.normalize_depth = true;
  settings.background = background;
  RenderOutput out = render(model, v.camera, v.pose, settings);
  const std::vector<float> surface_depth = median_depth(model, v.pose, out);
  const cv::Mat rgb(out.height, out.width, CV_32FC3, out.rgb.data());
  const cv::Mat target = v.rgb.load();

  ViewGeometry g;
  g.psnr = psnr(rgb, target);
  g.psnr_covered = psnr(rgb, target, covered);
  double surface = 0, n_covered = 0, within = 0, floaters = 0, floaters_covered = 0,
         floaters_expected = 0, floaters_disc = 0, holes = 0, holes_covered = 0;
  std::vector<double> abs_rel;
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x) {
      const double t = truth(y, x);
      if (!(t > 0)) continue;
      const size_t p = size_t(y) * truth.cols + x;
      const bool drawn = out.alpha[p] >= 0.5f;
      const double d = surface_depth[p];
      surface += 1;
      n_covered += covered(y, x);
      holes += !drawn;
      holes_covered += !drawn && covered(y, x);
      if (!drawn) continue;
      const double rel = std::abs(d - t) / t;
      abs_rel.push_back(rel);
      within += rel < 0.05;
      floaters += d < 0.9 * t;
      floaters_covered += d < 0.9 * t && covered(y, x);
      floaters_disc += d < 0.9 * t && discontinuity(y, x);
      floaters_expected += out.depth[p] < 0.9 * t;
    }
  if (picture) {
    // The render, with what went wrong painted over it: floaters red, holes on covered pixels
    // blue, and the surfaces no training view saw greyed out (nothing could reconstruct them).
    rgb.convertTo(*picture, CV_8UC3, 255.0);
    for (int y = 0; y < truth.rows; ++y)
      for (int x = 0; x < truth.cols; ++x) {
        const size_t p = size_t(y) * truth.cols + x;
        const double t = truth(y, x);
        cv::Vec3b& c = (*picture)(y, x);
        const bool drawn = out.alpha[p] >= 0.5f;
        if (!(t > 0)) continue;
        if (!covered(y, x)) {
          c = c / 3 + cv::Vec3b(85, 85, 85);
        } else if (!drawn) {
          c = kHoleColour;
        } else if (surface_depth[p] < 0.9 * t) {
          c = kFloaterColour;
        }
      }
  }
  g.coverage = ratio(n_covered, surface);
  g.depth_within_5pct = ratio(within, surface);
  g.floaters = ratio(floaters, surface);
  g.holes = ratio(holes, surface);
  g.holes_covered = ratio(holes_covered, n_covered);
  g.floaters_covered = ratio(floaters_covered, n_covered);
  g.floaters_expected_depth = ratio(floaters_expected, surface);
  g.floaters_at_discontinuity = ratio(floaters_disc, surface);
  g.floaters_away_from_discontinuity = ratio(floaters - floaters_disc, surface);
  if (!abs_rel.empty()) {
    auto mid = abs_rel.begin() + abs_rel.size() / 2;
    std::nth_element(abs_rel.begin(), mid, abs_rel.end());
    g.depth_abs_rel_median = *mid;
  }
  return g;
}

ViewGeometry mean_view_geometry(const GaussianModel& model, const Capture& capture,
                                const std::vector<int>& views, const std::vector<int>& train,
                                const Eigen::Vector3f& background,
                                std::vector<cv::Mat3b>* pictures) {
  double ViewGeometry::*fields[] = {&ViewGeometry::psnr,
                                    &ViewGeometry::psnr_covered,
                                    &ViewGeometry::coverage,
                                    &ViewGeometry::depth_abs_rel_median,
                                    &ViewGeometry::depth_within_5pct,
                                    &ViewGeometry::floaters,
                                    &ViewGeometry::floaters_covered,
                                    &ViewGeometry::floaters_expected_depth,
                                    &ViewGeometry::floaters_at_discontinuity,
                                    &ViewGeometry::floaters_away_from_discontinuity,
                                    &ViewGeometry::holes,
                                    &ViewGeometry::holes_covered};
  ViewGeometry mean;
  std::vector<ViewGeometry> all;
  for (const int v : views) {
    cv::Mat3b picture;
    all.push_back(
        view_geometry(model, capture, v, train, background, pictures ? &picture : nullptr));
    if (pictures) pictures->push_back(picture);
  }
  for (auto f : fields) {
    double sum = 0;
    int n = 0;
    for (const auto& g : all)
      if (!std::isnan(g.*f)) sum += g.*f, ++n;
    mean.*f = n ? sum / n : ViewGeometry::kNone;
  }
  return mean;
}

std::vector<LegendEntry> view_geometry_legend() {
  return {{"floater (>10% in front of the true surface)", kFloaterColour},
          {"hole (alpha < 0.5)", kHoleColour},
          {"surface no training view saw", cv::Vec3b(128, 128, 128)}};
}

}  // namespace gslift
