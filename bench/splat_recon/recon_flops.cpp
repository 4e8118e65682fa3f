#include "recon_flops.hpp"

#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/render_cache.hpp"

namespace gslift::bench {

StepFlops estimate_step_flops(const GaussianModel& model, const View& view) {
  RenderSettings settings;
  settings.depth = settings.normal = true;
  const RenderOutput out = render(model, view.camera, view.pose, settings);
  const RenderCache cache(out);
  const double pairs = static_cast<double>(cache.entries());
  const double pixels = static_cast<double>(out.width) * out.height;
  const double params =
      static_cast<double>(model.means.size() + model.log_scales.size() + model.quats.size() +
                          model.opacity_logits.size() + model.sh.size());
  StepFlops f;
  f.blend_forward = 40 * pairs;
  f.blend_backward = 90 * pairs;
  f.projection = 500 * static_cast<double>(model.size());
  // 5 windowed means forward + 3 adjoint filters, each 2 passes x 11 taps x (mul + add), on 3
  // channels, plus ~40 flops of per-pixel SSIM algebra and its derivative.
  f.ssim = (8 * 2 * 11 * 2 + 40) * 3 * pixels;
  f.adam = 12 * params;
  return f;
}

}  // namespace gslift::bench
