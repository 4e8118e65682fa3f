#include "nodes/inference/mask_silhouette.hpp"

#include <string>

#include <tbb/parallel_for.h>

#include "base/errors.hpp"

namespace gslift {

std::vector<char> centres_outside_mask(const std::vector<float>& means, const View& view,
                                       const cv::Mat1b& mask) {
  const Camera& cam = view.camera;
  if (mask.cols != cam.width || mask.rows != cam.height)
    throw InputError("mask of view '" + view.name + "' is " + std::to_string(mask.cols) + "x" +
                     std::to_string(mask.rows) + ", the view " + std::to_string(cam.width) + "x" +
                     std::to_string(cam.height));
  std::vector<char> outside(means.size() / 3, 0);
  tbb::parallel_for(size_t(0), outside.size(), [&](size_t g) {
    const Eigen::Vector3d x =
        view.pose.to_camera(Eigen::Vector3d(means[3 * g], means[3 * g + 1], means[3 * g + 2]));
    if (x.z() <= 1e-6) return;
    const double u = cam.fx * x.x() / x.z() + cam.cx, w = cam.fy * x.y() / x.z() + cam.cy;
    if (u < 0 || w < 0 || u >= cam.width || w >= cam.height) return;
    outside[g] = mask(static_cast<int>(w), static_cast<int>(u)) == 0;
  });
  return outside;
}

}  // namespace gslift
