#include "nodes/fusion/supervoxels.hpp"

#include <vector>

#include <tbb/parallel_for.h>
#include <Eigen/Core>

#include "base/errors.hpp"

namespace gslift {
namespace {

struct Centre {
  Eigen::Vector3d point, colour;
  int cell_x = 0, cell_y = 0;
};

// Splits every cluster into its 4-connected pieces and numbers them in raster order.
cv::Mat1i connected_pieces(const cv::Mat1i& labels) {
  const int w = labels.cols, h = labels.rows;
  cv::Mat1i out(h, w, -1);
  std::vector<int> stack;
  int next = 0;
  for (int p = 0; p < w * h; ++p) {
    const int l = labels(p / w, p % w);
    if (l < 0 || out(p / w, p % w) >= 0) continue;
    out(p / w, p % w) = next;
    stack.assign(1, p);
    while (!stack.empty()) {
      const int q = stack.back();
      stack.pop_back();
      const int x = q % w, y = q / w;
      const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
      for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
        if (labels(ny[k], nx[k]) != l || out(ny[k], nx[k]) >= 0) continue;
        out(ny[k], nx[k]) = next;
        stack.push_back(ny[k] * w + nx[k]);
      }
    }
    ++next;
  }
  return out;
}

}  // namespace

cv::Mat1i oversegment_rgbd(const cv::Mat& rgb, const cv::Mat1f& depth, const Camera& camera,
                           const SupervoxelOptions& options) {
  supervoxel_param_table().validate(options, "supervoxels");
  const int w = camera.width, h = camera.height;
  if (rgb.cols != w || rgb.rows != h || rgb.type() != CV_8UC3 || depth.cols != w || depth.rows != h)
    throw InputError("supervoxels: the RGB (" + std::to_string(rgb.cols) + "x" +
                     std::to_string(rgb.rows) + ") and depth (" + std::to_string(depth.cols) + "x" +
                     std::to_string(depth.rows) + ") differ from the " + std::to_string(w) + "x" +
                     std::to_string(h) + " camera");
  const int s = options.seed_spacing;
  const int cells_x = (w + s - 1) / s, cells_y = (h + s - 1) / s;
  auto point = [&](int u, int v) {
    const double z = depth(v, u);
    return Eigen::Vector3d((u + 0.5 - camera.cx) / camera.fx * z,
                           (v + 0.5 - camera.cy) / camera.fy * z, z);
  };
  // Returns a Vector3d, not the Eigen expression: `auto` would return a quotient that refers to
  // a temporary already gone (ASan: stack-use-after-scope).
  auto colour = [&](int u, int v) -> Eigen::Vector3d {
    const cv::Vec3b c = rgb.at<cv::Vec3b>(v, u);
    return Eigen::Vector3d(c[0], c[1], c[2]) / 255.0;
  };
  // Seeds: the first valid pixel of each grid cell in raster order; cell_seed[cell] = centre or -1.
  std::vector<Centre> centres;
  std::vector<int> cell_seed(size_t(cells_x) * cells_y, -1);
  for (int cy = 0; cy < cells_y; ++cy)
    for (int cx = 0; cx < cells_x; ++cx) {
      bool done = false;
      for (int v = cy * s; v < std::min(h, (cy + 1) * s) && !done; ++v)
        for (int u = cx * s; u < std::min(w, (cx + 1) * s) && !done; ++u)
          if (depth(v, u) > 0) {
            cell_seed[size_t(cy) * cells_x + cx] = static_cast<int>(centres.size());
            centres.push_back({point(u, v), colour(u, v), cx, cy});
            done = true;
          }
    }
  cv::Mat1i labels(h, w, -1);
  const double wc = options.colour_weight;
  const double ws =
      options.spatial_weight / (3.0 * options.seed_resolution * options.seed_resolution);
  for (int it = 0; it < options.iterations; ++it) {
    tbb::parallel_for(0, h, [&](int v) {
      for (int u = 0; u < w; ++u) {
        if (!(depth(v, u) > 0)) continue;
        const Eigen::Vector3d x = point(u, v), c = colour(u, v);
        const int cx = u / s, cy = v / s;
        int best = -1;
        double best_d = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int gx = cx + dx, gy = cy + dy;
            if (gx < 0 || gy < 0 || gx >= cells_x || gy >= cells_y) continue;
            const int k = cell_seed[size_t(gy) * cells_x + gx];
            if (k < 0) continue;
            const double d = wc * (c - centres[k].colour).squaredNorm() +
                             ws * (x - centres[k].point).squaredNorm();
            if (best < 0 || d < best_d) {
              best = k;
              best_d = d;
            }
          }
        labels(v, u) = best;
      }
    });
    // Centres move to the mean point and colour of their pixels (raster order: deterministic).
    std::vector<Eigen::Vector3d> sum_point(centres.size(), Eigen::Vector3d::Zero()),
        sum_colour(centres.size(), Eigen::Vector3d::Zero());
    std::vector<int> count(centres.size(), 0);
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        const int k = labels(v, u);
        if (k < 0) continue;
        sum_point[k] += point(u, v);
        sum_colour[k] += colour(u, v);
        ++count[k];
      }
    for (size_t k = 0; k < centres.size(); ++k)
      if (count[k] > 0) {
        centres[k].point = sum_point[k] / count[k];
        centres[k].colour = sum_colour[k] / count[k];
      }
  }
  return connected_pieces(labels);
}

const ParamTable<SupervoxelOptions>& supervoxel_param_table() {
  using O = SupervoxelOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("seed_spacing", &O::seed_spacing, "pixels between the grid seeds of the clusters", 2,
               1024)
          .add("seed_resolution", &O::seed_resolution,
               "R_seed, metres: normalises the spatial distance (VCCS)", 1e-4, 100)
          .add("colour_weight", &O::colour_weight, "w_c: weight of the RGB distance (VCCS)", 0, 100)
          .add("spatial_weight", &O::spatial_weight, "w_s: weight of the spatial distance (VCCS)",
               0, 100)
          .add("iterations", &O::iterations, "assignment / update rounds", 1, 100);
  return table;
}

}  // namespace gslift
