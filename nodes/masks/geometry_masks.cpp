#include "nodes/masks/geometry_masks.hpp"
#include "nodes/masks/label_segments.hpp"

#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <deque>
#include <numeric>

#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "base/random.hpp"

namespace gslift {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

// Disjoint sets over the pixels (path halving, union by index so roots are deterministic).
class PixelSets {
 public:
  explicit PixelSets(int n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int a) {
    while (parent_[a] != a) a = parent_[a] = parent_[parent_[a]];
    return a;
  }
  void join(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

// Dense ids in raster order of each set's first pixel; -1 where `member` is 0.
cv::Mat1i dense_labels(PixelSets& sets, const cv::Mat1b& member) {
  cv::Mat1i labels(member.size(), -1);
  std::vector<int> id_of_root(member.total(), -1);
  int next = 0;
  for (int i = 0; i < static_cast<int>(member.total()); ++i) {
    if (!member(i)) continue;
    int& id = id_of_root[sets.find(i)];
    if (id < 0) id = next++;
    labels(i) = id;
  }
  return labels;
}

// Camera-frame points of the valid pixels (z = depth), and their normals: the points are
// box-filtered over the valid pixels (normalised convolution), and a normal is the cross product of
// their differences normal_step pixels to either side, turned towards the camera. Invalid where
// either difference reaches an invalid pixel (zero normal).
void points_and_normals(const cv::Mat1f& depth, const Camera& cam, int step, cv::Mat3f& points,
                        cv::Mat3f& normals) {
  points.create(depth.size());
  cv::Mat1f valid(depth.size());
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x) {
      const float z = depth(y, x);
      valid(y, x) = z > 0 ? 1.f : 0.f;
      points(y, x) = z > 0 ? cv::Vec3f(static_cast<float>((x - cam.cx) / cam.fx * z),
                                       static_cast<float>((y - cam.cy) / cam.fy * z), z)
                           : cv::Vec3f(0, 0, 0);
    }
  cv::Mat3f sum;
  cv::Mat1f weight;
  const cv::Size window(2 * step + 1, 2 * step + 1);
  cv::boxFilter(points, sum, -1, window, {-1, -1}, false, cv::BORDER_CONSTANT);
  cv::boxFilter(valid, weight, -1, window, {-1, -1}, false, cv::BORDER_CONSTANT);
  normals = cv::Mat3f(depth.size(), cv::Vec3f(0, 0, 0));
  auto smooth = [&](int y, int x) { return cv::Vec3f(sum(y, x) / weight(y, x)); };
  for (int y = step; y < depth.rows - step; ++y)
    for (int x = step; x < depth.cols - step; ++x) {
      if (!valid(y, x) || !valid(y, x - step) || !valid(y, x + step) || !valid(y - step, x) ||
          !valid(y + step, x))
        continue;
      const cv::Vec3f n = (smooth(y, x + step) - smooth(y, x - step))
                              .cross(smooth(y + step, x) - smooth(y - step, x));
      const float len = static_cast<float>(cv::norm(n));
      if (len <= 0) continue;
      normals(y, x) = (n.dot(points(y, x)) > 0 ? -1.f : 1.f) * n / len;
    }
}

// The segments of `parent` (labels, -1 = none) cut further at the barrier pixels: neighbours are
// joined when `joined` allows, they share a parent segment and neither is a barrier; then each
// barrier pixel takes the segment of a joined neighbour of its parent, breadth-first from the
// segments (a crease band goes to the faces beside it, not to no segment); barrier pixels no
// segment reaches (a thin part all crease) form segments of their own. Every segment lies inside
// one parent segment, so the granularities nest.
template <class Joined>
cv::Mat1i refined_segments(const cv::Mat1i& parent, const cv::Mat1b& barrier,
                           const cv::Mat1b& valid, const Joined& joined) {
  const int w = valid.cols, h = valid.rows, n = static_cast<int>(valid.total());
  auto related = [&](int a, int b) {
    return parent(a) >= 0 && parent(a) == parent(b) && joined(a, b);
  };
  PixelSets sets(n);
  cv::Mat1b open(valid.size());
  for (int i = 0; i < n; ++i) open(i) = valid(i) && !barrier(i) ? 255 : 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int i = y * w + x;
      for (const int j : {x + 1 < w ? i + 1 : -1, y + 1 < h ? i + w : -1})
        if (j >= 0 && open(i) && open(j) && related(i, j)) sets.join(i, j);
    }
  cv::Mat1i labels = dense_labels(sets, open);
  std::deque<int> queue;
  for (int i = 0; i < n; ++i)
    if (labels(i) >= 0) queue.push_back(i);
  auto neighbours = [&](int i) {
    const int x = i % w, y = i / w;
    return std::array<int, 4>{x > 0 ? i - 1 : -1, x + 1 < w ? i + 1 : -1, y > 0 ? i - w : -1,
                              y + 1 < h ? i + w : -1};
  };
  while (!queue.empty()) {
    const int i = queue.front();
    queue.pop_front();
    for (const int j : neighbours(i))
      if (j >= 0 && valid(j) && labels(j) < 0 && related(i, j)) {
        labels(j) = labels(i);
        queue.push_back(j);
      }
  }
  double top = -1;
  cv::minMaxLoc(labels, nullptr, &top);
  PixelSets rest(n);
  cv::Mat1b left(valid.size());
  for (int i = 0; i < n; ++i) left(i) = valid(i) && labels(i) < 0 && parent(i) >= 0 ? 255 : 0;
  for (int i = 0; i < n; ++i)
    if (left(i))
      for (const int j : neighbours(i))
        if (j > i && left(j) && related(i, j)) rest.join(i, j);
  const cv::Mat1i extra = dense_labels(rest, left);
  for (int i = 0; i < n; ++i)
    if (extra(i) >= 0) labels(i) = static_cast<int>(top) + 1 + extra(i);
  return labels;
}

struct Plane {
  Eigen::Vector3d n;  // unit
  double d = 0;       // n . p + d = 0
};

bool plane_inlier(const Plane& plane, const cv::Vec3f& p, const cv::Vec3f& normal, double distance,
                  double cos_angle) {
  const Eigen::Vector3d q(p[0], p[1], p[2]);
  return std::abs(plane.n.dot(q) + plane.d) < distance * p[2] &&
         std::abs(plane.n.dot(Eigen::Vector3d(normal[0], normal[1], normal[2]))) > cos_angle;
}

// Least-squares plane through the points of `mask` (smallest principal axis).
Plane fit_plane(const cv::Mat3f& points, const cv::Mat1b& mask) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  int n = 0;
  for (int i = 0; i < static_cast<int>(mask.total()); ++i) {
    if (!mask(i)) continue;
    const cv::Vec3f& p = points(i);
    mean += Eigen::Vector3d(p[0], p[1], p[2]);
    ++n;
  }
  mean /= n;
  for (int i = 0; i < static_cast<int>(mask.total()); ++i) {
    if (!mask(i)) continue;
    const cv::Vec3f& p = points(i);
    const Eigen::Vector3d q = Eigen::Vector3d(p[0], p[1], p[2]) - mean;
    cov += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Plane plane;
  plane.n = eig.eigenvectors().col(0);
  plane.d = -plane.n.dot(mean);
  return plane;
}

// Sequential RANSAC for the dominant planes among the pixels with a normal. Hypotheses from three
// random pixels, scored on every 8th pixel of every 8th row; the best is refitted on its inliers,
// and each 8-connected piece of its inliers of at least min_pixels becomes a plane segment (a
// floor another object cuts in two is two segments: each piece alone is what a mask can be).
cv::Mat1i dominant_planes(const cv::Mat3f& points, const cv::Mat3f& normals,
                          const GeometryMaskOptions& o, int& count) {
  const double cos_angle = std::cos(o.plane_angle * kDegree);
  cv::Mat1i planes(points.size(), 0);
  count = 0;
  std::vector<int> candidates;
  for (int i = 0; i < static_cast<int>(normals.total()); ++i)
    if (normals(i) != cv::Vec3f(0, 0, 0)) candidates.push_back(i);
  const int min_pixels = static_cast<int>(std::ceil(o.plane_min_fraction * candidates.size()));
  RandomStream rng(stream_seed(0, "masks.geometry.planes"));
  for (int round = 0; round < o.max_planes; ++round) {
    std::vector<int> free;
    for (int i : candidates)
      if (planes(i) == 0) free.push_back(i);
    if (static_cast<int>(free.size()) < std::max(min_pixels, 3)) break;
    std::vector<int> probe;
    for (int i : free)
      if ((i / points.cols) % 8 == 0 && (i % points.cols) % 8 == 0) probe.push_back(i);
    Plane best;
    int best_score = -1;
    for (int it = 0; it < o.ransac_iterations; ++it) {
      const cv::Vec3f a = points(free[rng.below(free.size())]),
                      b = points(free[rng.below(free.size())]),
                      c = points(free[rng.below(free.size())]);
      const cv::Vec3f n = (b - a).cross(c - a);
      const double len = cv::norm(n);
      if (len < 1e-12) continue;
      Plane h;
      h.n = Eigen::Vector3d(n[0], n[1], n[2]) / len;
      h.d = -h.n.dot(Eigen::Vector3d(a[0], a[1], a[2]));
      int score = 0;
      for (int i : probe)
        score += plane_inlier(h, points(i), normals(i), o.plane_distance, cos_angle);
      if (score > best_score) {
        best_score = score;
        best = h;
      }
    }
    if (best_score <= 0) break;
    cv::Mat1b inliers(points.size(), uchar(0));
    for (int pass = 0; pass < 2; ++pass) {  // inliers of the hypothesis, then of the refit
      inliers.setTo(0);
      for (int i : free)
        inliers(i) =
            plane_inlier(best, points(i), normals(i), o.plane_distance, cos_angle) ? 255 : 0;
      if (pass == 0 && cv::countNonZero(inliers) >= 3) best = fit_plane(points, inliers);
    }
    // The normal test leaves speckle where the depth noise tilts a normal, and misses the pixels
    // without a normal (beside holes and the border): any free pixel near the plane within
    // normal_step pixels of an inlier joins it, so the plane's neighbours are not joined through
    // the speckle.
    cv::Mat1b near;
    cv::dilate(
        inliers, near,
        cv::getStructuringElement(cv::MORPH_RECT, {2 * o.normal_step + 1, 2 * o.normal_step + 1}));
    for (int i = 0; i < static_cast<int>(points.total()); ++i) {
      const cv::Vec3f& p = points(i);
      if (near(i) && !inliers(i) && planes(i) == 0 && p[2] > 0 &&
          std::abs(best.n.dot(Eigen::Vector3d(p[0], p[1], p[2])) + best.d) <
              o.plane_distance * p[2])
        inliers(i) = 255;
    }
    cv::Mat1i pieces;
    cv::Mat stats, centroids;
    const int n = cv::connectedComponentsWithStats(inliers, pieces, stats, centroids, 8, CV_32S);
    bool kept = false;
    for (int k = 1; k < n; ++k) {
      if (stats.at<int>(k, cv::CC_STAT_AREA) < min_pixels) continue;
      ++count;
      planes.setTo(count, pieces == k);
      kept = true;
    }
    if (!kept) break;  // the best plane left has no piece large enough: none smaller has either
  }
  return planes;
}

}  // namespace

GeometrySegments geometry_segments(const cv::Mat& depth_in, const Camera& camera,
                                   const GeometryMaskOptions& o, const std::string& where) {
  geometry_mask_param_table().validate(o, where);
  if (depth_in.empty()) throw InputError(where + ": the depth map is empty");
  if (depth_in.type() != CV_32FC1)
    throw InputError(where + ": the depth map is not CV_32FC1 metres (type " +
                     std::to_string(depth_in.type()) + ")");
  if (depth_in.cols != camera.width || depth_in.rows != camera.height)
    throw InputError(where + ": the depth map is " + std::to_string(depth_in.cols) + "x" +
                     std::to_string(depth_in.rows) + ", its camera " +
                     std::to_string(camera.width) + "x" + std::to_string(camera.height));
  if (o.median % 2 == 0)
    throw InputError(where + ": median must be 1, 3 or 5 (an odd aperture), not " +
                     std::to_string(o.median));
  cv::Mat1f depth;
  depth_in.copyTo(depth);
  cv::patchNaNs(depth, 0);
  depth.setTo(0, depth < 0);
  if (o.median > 1) {
    // The median of a pixel beside a hole mixes in zeros; a pixel invalid before stays invalid.
    cv::Mat1f filtered;
    cv::medianBlur(depth, filtered, o.median);
    filtered.setTo(0, depth == 0);
    depth = filtered;
  }
  cv::Mat3f points, normals;
  points_and_normals(depth, camera, o.normal_step, points, normals);

  GeometrySegments out;
  out.planes = dominant_planes(points, normals, o, out.plane_count);

  // Creases: the normals normal_step to either side (x or y) differ by more than crease_angle.
  // A crease is concave when the normals face each other, (n_a - n_b) . (p_a - p_b) < 0 (the
  // local convexity criterion of LCCP, Stein et al., CVPR 2014): where an object meets the floor,
  // a wall or another object; convex creases are an object's own edges. Beside a hole a
  // pixel has no normal to compare and counts as both.
  const double cos_crease = std::cos(o.crease_angle * kDegree);
  const int s = o.normal_step;
  cv::Mat1b any_crease(depth.size(), uchar(0)), concave(depth.size(), uchar(0));
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x) {
      if (depth(y, x) <= 0 || out.planes(y, x) > 0) continue;  // a plane has no crease inside
      auto turn = [&](int y0, int x0, int y1, int x1) {
        if (y0 < 0 || x0 < 0 || y1 >= depth.rows || x1 >= depth.cols) return;
        const cv::Vec3f &na = normals(y0, x0), &nb = normals(y1, x1);
        const bool missing = na == cv::Vec3f(0, 0, 0) || nb == cv::Vec3f(0, 0, 0);
        if (!missing && na.dot(nb) >= cos_crease) return;
        any_crease(y, x) = 255;
        if (missing || (na - nb).dot(points(y0, x0) - points(y1, x1)) < 0) concave(y, x) = 255;
      };
      turn(y, x - s, y, x + s);
      turn(y - s, x, y + s, x);
    }

  // A plane's piece is one connected surface by construction: its neighbours are joined even
  // where a floor seen at a grazing angle steps by more than depth_jump from row to row.
  auto joined = [&](int a, int b) {
    const float za = depth(a), zb = depth(b);
    return za > 0 && zb > 0 && out.planes(a) == out.planes(b) &&
           (out.planes(a) > 0 || std::abs(za - zb) <= o.depth_jump * std::min(za, zb));
  };
  const cv::Mat1b valid = depth > 0;
  const cv::Mat1i whole = refined_segments(cv::Mat1i(depth.size(), 0),
                                           cv::Mat1b(depth.size(), uchar(0)), valid, joined);
  const cv::Mat1i object = refined_segments(whole, concave, valid, joined);
  out.labels = {whole, object, refined_segments(object, any_crease, valid, joined)};
  return out;
}

std::vector<Mask> geometry_masks(const cv::Mat& depth, const Camera& camera,
                                 const GeometryMaskOptions& o, const std::string& where) {
  const GeometrySegments seg = geometry_segments(depth, camera, o, where);
  std::vector<Mask> out;
  for (size_t g = 0; g < seg.labels.size(); ++g)
    append_label_segments(seg.labels[g], static_cast<int>(g), o.keep, out);
  return out;
}

MaskSet geometry_mask_set(const Capture& capture, const GeometryMaskOptions& o) {
  const std::vector<int> views = capture.views_named(o.keep.views);
  for (int v : views)
    if (!capture.views[v].depth.present())
      throw InputError("masks.geometry: view '" + capture.views[v].name + "' of '" + capture.name +
                       "' has no depth prior");
  MaskSet set;
  set.views.resize(views.size());
  tbb::parallel_for(size_t(0), views.size(), [&](size_t i) {
    const View& view = capture.views[views[i]];
    cv::Mat depth = view.depth.load();
    const cv::Size size(view.camera.width, view.camera.height);
    if (!depth.empty() && depth.size() != size)
      cv::resize(depth, depth, size, 0, 0, cv::INTER_NEAREST);
    set.views[i].view = view.name;
    set.views[i].masks =
        geometry_masks(depth, view.camera, o, "masks.geometry: view '" + view.name + "'");
  });
  std::string empty;
  size_t masks = 0;
  for (const ViewMasks& vm : set.views) {
    masks += vm.masks.size();
    if (vm.masks.empty()) empty += (empty.empty() ? "" : ", ") + vm.view;
  }
  if (masks == 0)
    throw InputError("masks.geometry: no view of '" + capture.name +
                     "' gives a mask: is its depth prior all invalid (0)?");
  if (!empty.empty())
    spdlog::warn(
        "masks.geometry: no mask in view(s) {} (no valid depth, or only segments under "
        "min_area)",
        empty);
  return set;
}

const ParamTable<GeometryMaskOptions>& geometry_mask_param_table() {
  using O = GeometryMaskOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("median", &O::median, "median filter aperture on the depth (1 = none, 3, 5)", 1, 5)
          .add("normal_step", &O::normal_step, "pixels to either side whose points give a normal",
               1, 50)
          .add("depth_jump", &O::depth_jump,
               "neighbours further apart than this fraction of their depth are not joined", 1e-4,
               10)
          .add("crease_angle", &O::crease_angle,
               "degrees the normal turns across 2 normal_step pixels that cut parts apart", 0.1,
               180)
          .add("max_planes", &O::max_planes, "most dominant planes searched", 0, 100)
          .add("plane_min_fraction", &O::plane_min_fraction,
               "smallest plane piece, as a fraction of the pixels with a normal", 0, 1)
          .add("plane_distance", &O::plane_distance,
               "plane inlier distance as a fraction of the depth", 0, 1)
          .add("plane_angle", &O::plane_angle, "plane inlier normal angle, degrees", 0, 90)
          .add("ransac_iterations", &O::ransac_iterations, "plane hypotheses per plane", 1, 100000)
          .nest(&O::keep, segment_keep_param_table());
  return table;
}

}  // namespace gslift
