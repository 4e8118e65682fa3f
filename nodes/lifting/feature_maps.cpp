#include "nodes/lifting/feature_maps.hpp"

#include <string>

#include "base/errors.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/render_cache.hpp"

namespace gslift {

TrainingFeatureMaps render_training_feature_maps(const GaussianModel& model, const Capture& capture,
                                                 const MaskSet& masks, bool with_contribution) {
  if (model.feature_dim <= 0)
    throw InputError(
        "the model has no feature channels (train them first, e.g. "
        "features.contrastive)");
  TrainingFeatureMaps out;
  for (size_t v = 0; v < masks.views.size(); ++v) {
    const ViewMasks& vm = masks.views[v];
    const int index = capture.find_view(vm.view);
    if (index < 0)
      throw InputError("masks name the view '" + vm.view + "', which is not in the capture '" +
                       capture.name + "'");
    const View& view = capture.views[index];
    for (const Mask& m : vm.masks)
      if (m.pixels.cols != view.camera.width || m.pixels.rows != view.camera.height)
        throw InputError("a mask of view '" + vm.view + "' is " + std::to_string(m.pixels.cols) +
                         "x" + std::to_string(m.pixels.rows) + " but the view is " +
                         std::to_string(view.camera.width) + "x" +
                         std::to_string(view.camera.height));
    if (view.held_out) continue;
    out.mask_views.push_back(static_cast<int>(v));
    out.capture_views.push_back(index);
    out.masks.views.push_back(vm);
  }
  if (out.masks.views.empty())
    throw InputError("no training view of the capture '" + capture.name + "' has masks");

  if (with_contribution) out.contribution.assign(model.size(), 0.f);
  RenderSettings settings;
  settings.rgb = false;
  settings.features = true;
  for (const int index : out.capture_views) {
    const View& view = capture.views[index];
    RenderOutput rendered = render(model, view.camera, view.pose, settings);
    if (with_contribution) {
      const std::vector<float> ones(static_cast<size_t>(rendered.width) * rendered.height, 1.f);
      RenderCache(rendered).backward(ones.data(), 1, out.contribution.data());
    }
    FeatureMap map;
    map.width = rendered.width;
    map.height = rendered.height;
    map.dim = rendered.feature_dim;
    map.values = std::move(rendered.features);
    out.maps.push_back(std::move(map));
  }
  return out;
}

}  // namespace gslift
