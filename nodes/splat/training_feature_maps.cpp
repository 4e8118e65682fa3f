#include "nodes/splat/training_feature_maps.hpp"

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
  for (const MaskView& mv : training_mask_views(capture, masks)) {
    out.mask_views.push_back(mv.mask_view);
    out.capture_views.push_back(mv.capture_view);
    out.masks.views.push_back(masks.views[mv.mask_view]);
  }

  if (with_contribution) out.contribution.assign(model.size(), 0.f);
  RenderSettings settings;
  settings.rgb = false;
  settings.features = true;
  for (const int index : out.capture_views) {
    const View& view = capture.views[index];
    RenderOutput rendered = render(model, view.camera, view.pose, settings);
    if (with_contribution) add_blend_weights(rendered, out.contribution.data());
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
