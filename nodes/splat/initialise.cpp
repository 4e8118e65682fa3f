#include "nodes/splat/initialise.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <open3d/geometry/KDTreeFlann.h>
#include <open3d/geometry/PointCloud.h>
#include <Eigen/Geometry>

#include "base/errors.hpp"
#include "base/random.hpp"
#include "nodes/splat/depth_normals.hpp"

namespace gslift {
namespace {

constexpr double kSH0 = 0.28209479177387814;  // C0, the degree-0 SH basis constant

bool has_depth(const Capture& capture, const std::vector<int>& views) {
  for (int v : views)
    if (!capture.views[v].depth.present()) return false;
  return !views.empty();
}

}  // namespace

ColouredPoints backproject_depth(const Capture& capture, const std::vector<int>& views,
                                 int pixel_stride) {
  ColouredPoints out;
  std::vector<double> footprints;
  const int stride = std::max(1, pixel_stride);
  for (int index : views) {
    const View& view = capture.views[index];
    const cv::Mat depth = view.depth.load();
    const cv::Mat rgb = view.rgb.load();
    if (depth.empty()) continue;
    if (depth.type() != CV_32FC1 || depth.size() != rgb.size() || rgb.type() != CV_8UC3)
      throw InputError("view '" + view.name + "': depth prior must be CV_32F and the size of its " +
                       "RGB image (" + std::to_string(rgb.cols) + "x" + std::to_string(rgb.rows) +
                       "), got " + std::to_string(depth.cols) + "x" + std::to_string(depth.rows));
    const Camera& cam = view.camera;
    const Eigen::Matrix3d R_t = view.pose.R.transpose();
    const Eigen::Vector3d centre = view.pose.centre();
    const double focal = 0.5 * (cam.fx + cam.fy);
    const cv::Mat normals =
        normals_from_depth(depth, cam, view.pose, 0.1, 1, kPriorNormalSmoothing);
    for (int v = 0; v < depth.rows; v += stride) {
      for (int u = 0; u < depth.cols; u += stride) {
        const float d = depth.at<float>(v, u);
        if (!(d > 0.f) || !std::isfinite(d)) continue;
        const Eigen::Vector3d cam_point(d * (u + 0.5 - cam.cx) / cam.fx,
                                        d * (v + 0.5 - cam.cy) / cam.fy, d);
        out.xyz.push_back(R_t * cam_point + centre);  // x_world = R^T (x_cam - t)
        const cv::Vec3b c = rgb.at<cv::Vec3b>(v, u);
        out.rgb.emplace_back(c[0] / 255.0, c[1] / 255.0, c[2] / 255.0);
        const cv::Vec3f n = normals.at<cv::Vec3f>(v, u);
        out.normals.emplace_back(n[0], n[1], n[2]);
        footprints.push_back(d / focal);
      }
    }
  }
  if (!footprints.empty()) {
    auto mid = footprints.begin() + footprints.size() / 2;
    std::nth_element(footprints.begin(), mid, footprints.end());
    out.median_footprint = *mid;
  }
  return out;
}

ColouredPoints sparse_points(const Capture& capture) {
  ColouredPoints out;
  for (size_t i = 0; i < capture.points.size(); ++i) {
    out.xyz.push_back(capture.points.xyz[i].cast<double>());
    const auto& c = capture.points.rgb.size() > i ? capture.points.rgb[i]
                                                  : Eigen::Matrix<uint8_t, 3, 1>(128, 128, 128);
    out.rgb.emplace_back(c[0] / 255.0, c[1] / 255.0, c[2] / 255.0);
  }
  return out;
}

namespace {

// The error Open3D's VoxelDownSample would raise ("voxel_size is too small", in terminal
// colours, naming nothing), raised here with the numbers: its grid indexes voxels with int, so
// the points must span fewer than 2^31 voxels along every axis. An extreme pose or focal length
// (a camera 1e20 m out, a focal of 1e-9 px) is what breaks it.
void check_voxel_grid(const ColouredPoints& points, double voxel) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& x : points.xyz) {
    if (!x.allFinite())
      throw InputError("initialise: a point is NaN or Inf (" + std::to_string(x.x()) + ", " +
                       std::to_string(x.y()) + ", " + std::to_string(x.z()) + ")");
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  if (voxel <= 0 || points.xyz.empty()) return;
  const double span = (hi - lo).maxCoeff() + voxel;
  if (!std::isfinite(voxel) || !(span / voxel < std::numeric_limits<int>::max()))
    throw InputError("initialise: voxel size " + std::to_string(voxel) + " m for points spanning " +
                     std::to_string(span) +
                     " m needs more than 2^31 voxels per axis (an extreme pose or focal length?)");
}

// The training views with the most extreme camera centre and focal length, to name in an error.
std::string extreme_views(const Capture& capture, const std::vector<int>& views) {
  if (views.empty()) return {};
  int far = views[0], small = views[0], large = views[0];
  const auto focal = [&](int v) {
    return std::min(capture.views[v].camera.fx, capture.views[v].camera.fy);
  };
  const auto dist = [&](int v) { return capture.views[v].pose.centre().norm(); };
  for (int v : views) {
    if (dist(v) > dist(far)) far = v;
    if (focal(v) < focal(small)) small = v;
    if (focal(v) > focal(large)) large = v;
  }
  const auto name = [&](int v) { return "view '" + capture.views[v].name + "'"; };
  return name(far) + " has the camera farthest from the origin (" + std::to_string(dist(far)) +
         " m), " + name(small) + " the smallest focal length (" + std::to_string(focal(small)) +
         " px), " + name(large) + " the largest (" + std::to_string(focal(large)) + " px)";
}

}  // namespace

GaussianModel gaussians_from_points(const ColouredPoints& points, double voxel,
                                    const InitialiseOptions& options) {
  check_voxel_grid(points, voxel);
  open3d::geometry::PointCloud cloud;
  cloud.points_ = points.xyz;
  cloud.colors_ = points.rgb;
  cloud.normals_ = points.normals;  // averaged per voxel by VoxelDownSample
  std::shared_ptr<open3d::geometry::PointCloud> down =
      voxel > 0 ? cloud.VoxelDownSample(voxel)
                : std::make_shared<open3d::geometry::PointCloud>(cloud);
  const size_t n = down->points_.size();

  GaussianModel model;
  model.sh_degree = options.sh_degree;
  model.feature_dim = options.feature_dim;
  model.resize(n);
  const int K = GaussianModel::sh_coeffs(options.sh_degree);
  const float logit = std::log(options.opacity / (1 - options.opacity));
  open3d::geometry::KDTreeFlann tree(*down);
  std::vector<int> neighbours;
  std::vector<double> dist2;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = down->points_[i];
    // 3 nearest neighbours other than the point itself (the query returns it first).
    const int found = tree.SearchKNN(p, 4, neighbours, dist2);
    double sum = 0;
    for (int k = 1; k < found; ++k)
      sum += options.scale_distance == NeighbourDistance::Rms ? dist2[k] : std::sqrt(dist2[k]);
    const double mean = found > 1 ? sum / (found - 1) : 0;
    // log of the distance floored at sqrt(1e-7): RMS = sqrt(mean of squares), mean as it is.
    const double log_distance = options.scale_distance == NeighbourDistance::Rms
                                    ? 0.5 * std::log(std::max(mean, 1e-7))
                                    : std::log(std::max(mean, std::sqrt(1e-7)));
    const float log_scale = static_cast<float>(log_distance + std::log(options.scale_factor));
    // The voxel's mean normal; views that see a thin surface from both sides cancel out, and such
    // voxels stay isotropic.
    const Eigen::Vector3d normal = down->HasNormals() ? down->normals_[i] : Eigen::Vector3d::Zero();
    const bool oriented = options.normal_thickness != 1 && normal.norm() > 0.5;
    if (oriented) {
      const Eigen::Quaterniond q =
          Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal.normalized());
      model.quats[i * 4] = static_cast<float>(q.w());
      model.quats[i * 4 + 1] = static_cast<float>(q.x());
      model.quats[i * 4 + 2] = static_cast<float>(q.y());
      model.quats[i * 4 + 3] = static_cast<float>(q.z());
    }
    for (int k = 0; k < 3; ++k) {
      model.means[i * 3 + k] = static_cast<float>(p[k]);
      model.log_scales[i * 3 + k] = log_scale;
      model.sh[i * K * 3 + k] = static_cast<float>((down->colors_[i][k] - 0.5) / kSH0);
    }
    if (oriented)
      model.log_scales[i * 3 + 2] += static_cast<float>(std::log(options.normal_thickness));
    model.opacity_logits[i] = logit;
  }
  return model;
}

const EnumNames<NeighbourDistance>& neighbour_distance_names() {
  static const EnumNames<NeighbourDistance> names = {{NeighbourDistance::Rms, "rms"},
                                                     {NeighbourDistance::Mean, "mean"}};
  return names;
}

const EnumNames<InitSource>& init_source_names() {
  static const EnumNames<InitSource> names = {{InitSource::Auto, "auto"},
                                              {InitSource::Depth, "depth"},
                                              {InitSource::Points, "points"},
                                              {InitSource::Random, "random"}};
  return names;
}

double scene_extent(const Capture& capture) {
  std::vector<Eigen::Vector3d> centres;
  for (int v : capture.train_views()) centres.push_back(capture.views[v].pose.centre());
  if (centres.size() < 2) return 1.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& c : centres) mean += c;
  mean /= static_cast<double>(centres.size());
  double radius = 0;
  for (const auto& c : centres) radius = std::max(radius, (c - mean).norm());
  return radius > 0 ? 1.1 * radius : 1.0;
}

double reconstruction_extent(const Capture& capture, const std::vector<float>& means) {
  const double cameras = scene_extent(capture);
  const std::vector<int> train = capture.train_views();
  if (train.empty() || means.size() < 3) return cameras;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int v : train) centre += capture.views[v].pose.centre();
  centre /= static_cast<double>(train.size());
  std::vector<double> distances;
  for (size_t i = 0; i + 2 < means.size(); i += 3)
    distances.push_back((Eigen::Vector3d(means[i], means[i + 1], means[i + 2]) - centre).norm());
  auto middle = distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2);
  std::nth_element(distances.begin(), middle, distances.end());
  return std::max(cameras, *middle);
}

ColouredPoints random_volume_points(const Capture& capture, const std::vector<int>& views,
                                    int count, double near, double far, double min_view_fraction,
                                    uint64_t seed) {
  ColouredPoints out;
  if (views.size() < 2)
    throw InputError("capture '" + capture.name +
                     "' has neither sparse points nor a depth prior, and random points need two "
                     "training views to share a volume");
  std::vector<cv::Mat> rgb;
  for (const int v : views) rgb.push_back(capture.views[v].rgb.load());
  RandomStream rng(stream_seed(seed, "random_volume_points"));
  const int min_views = std::max(2, static_cast<int>(std::ceil(min_view_fraction * views.size())));
  // Rejection sampling; the cap only guards views that share (almost) nothing.
  const int64_t max_tries = 200 * static_cast<int64_t>(count);
  for (int64_t tries = 0; static_cast<int>(out.xyz.size()) < count && tries < max_tries; ++tries) {
    const int a = rng.below(static_cast<int>(views.size()));
    const View& va = capture.views[views[a]];
    const Camera& c = va.camera;
    const double u = rng.uniform(0, c.width), v = rng.uniform(0, c.height);
    const double z = rng.uniform(near, far);
    const Eigen::Vector3d cam((u - c.cx) / c.fx * z, (v - c.cy) / c.fy * z, z);
    const Eigen::Vector3d world = va.pose.R.transpose() * (cam - va.pose.t);
    int seen_by = 1;  // view a
    for (size_t b = 0; b < views.size(); ++b) {
      if (static_cast<int>(b) == a) continue;
      const View& vb = capture.views[views[b]];
      const Eigen::Vector3d p = vb.pose.to_camera(world);
      if (p.z() <= 0) continue;
      const double ub = vb.camera.fx * p.x() / p.z() + vb.camera.cx;
      const double vb_ = vb.camera.fy * p.y() / p.z() + vb.camera.cy;
      seen_by += ub >= 0 && vb_ >= 0 && ub < vb.camera.width && vb_ < vb.camera.height;
    }
    if (seen_by < min_views) continue;
    const cv::Vec3b colour = rgb[a].at<cv::Vec3b>(static_cast<int>(v), static_cast<int>(u));
    out.xyz.push_back(world);
    out.rgb.emplace_back(colour[0] / 255.0, colour[1] / 255.0, colour[2] / 255.0);
  }
  if (out.xyz.empty())
    throw InputError("capture '" + capture.name +
                     "': no two training views see a common volume between the near and far "
                     "distances; nothing to initialise from");
  return out;
}

GaussianModel initialise_gaussians(const Capture& capture, const InitialiseOptions& options) {
  const std::vector<int> train = capture.train_views();
  InitSource source = options.source;
  if (source == InitSource::Auto)
    source = has_depth(capture, train)     ? InitSource::Depth
             : !capture.points.xyz.empty() ? InitSource::Points
                                           : InitSource::Random;
  const std::string where = "capture '" + capture.name + "': ";
  if (source == InitSource::Depth) {
    const ColouredPoints points = backproject_depth(capture, train, options.pixel_stride);
    if (points.xyz.empty())
      throw InputError(where +
                       "no valid depth prior pixel in the training views to initialise from");
    try {
      return gaussians_from_points(points, options.footprint_factor * points.median_footprint,
                                   options);
    } catch (const InputError& e) {
      throw InputError(where + e.what() + "; " + extreme_views(capture, train));
    }
  }
  if (source == InitSource::Random) {
    const double extent = scene_extent(capture);
    return gaussians_from_points(
        random_volume_points(capture, train, options.random_points, options.random_near * extent,
                             options.random_far * extent, options.random_min_views, options.seed),
        0.0, options);
  }
  const ColouredPoints points = sparse_points(capture);
  if (points.xyz.empty()) throw InputError(where + "has no sparse points to initialise from");
  return gaussians_from_points(points, options.points_voxel, options);
}

}  // namespace gslift
