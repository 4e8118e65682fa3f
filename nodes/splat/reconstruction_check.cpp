#include "nodes/splat/reconstruction_check.hpp"

#include <cmath>
#include <cstdio>

namespace gslift {

namespace {

std::string fixed(double v, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

}  // namespace

std::string reconstruction_failure(const ReconstructResult& r, double min_train_psnr) {
  if (r.model.size() == 0) {
    std::string text = "the reconstruction ended with 0 Gaussians (" +
                       std::to_string(r.initial_gaussians) + " at the start, scene extent " +
                       fixed(r.scene_extent, 3) + ")";
    if (r.emptied)
      text += ": the pruning round at step " + std::to_string(r.emptied->step) +
              " removed the last ones, " + std::to_string(r.emptied->scale) +
              " larger than prune_max_scale x scene extent, " + std::to_string(r.emptied->opacity) +
              " below prune_opacity, " + std::to_string(r.emptied->free_space) +
              " by free-space pruning";
    return text;
  }
  if (min_train_psnr > 0 && std::isfinite(r.train_psnr) && r.train_psnr < min_train_psnr)
    return "the reconstruction's train PSNR is " + fixed(r.train_psnr, 1) +
           " dB, under the floor min_train_psnr = " + fixed(min_train_psnr, 1) +
           " dB: " + std::to_string(r.model.size()) + " Gaussians after " +
           std::to_string(r.iterations_run) + " steps, scene extent " + fixed(r.scene_extent, 3);
  return {};
}

}  // namespace gslift
