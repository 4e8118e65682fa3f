#include "nodes/fusion/render_semantics.hpp"

#include <algorithm>

#include "base/errors.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/render_cache.hpp"

namespace gslift {
namespace {

void fill_confident(float* d, int classes, int label, float confidence) {
  std::fill(d, d + classes, classes > 1 ? (1.f - confidence) / (classes - 1) : 1.f);
  d[label] = confidence;
}

}  // namespace

std::vector<float> gaussian_class_probabilities(const std::vector<int32_t>& instance_ids,
                                                const std::vector<int>& instance_class, int classes,
                                                const RenderSemanticsOptions& options) {
  std::vector<float> out(instance_ids.size() * classes, 1.f / classes);
  for (size_t g = 0; g < instance_ids.size(); ++g) {
    const int32_t k = instance_ids[g];
    float* d = out.data() + g * classes;
    if (k < 0) {
      fill_confident(d, classes, 0, options.background_confidence);
      continue;
    }
    if (k >= static_cast<int32_t>(instance_class.size()))
      throw InputError("fusion.render_semantics: Gaussian " + std::to_string(g) +
                       " has instance id " + std::to_string(k) + " but there are " +
                       std::to_string(instance_class.size()) + " instances");
    if (instance_class[k] >= 0)
      fill_confident(d, classes, instance_class[k], options.instance_confidence);
  }
  return out;
}

std::vector<float> background_distribution(int classes, const RenderSemanticsOptions& options) {
  std::vector<float> d(classes);
  fill_confident(d.data(), classes, 0, options.background_confidence);
  return d;
}

SemanticView semantics_from_blend(const std::string& name, std::vector<float> blend,
                                  const std::vector<float>& background, int classes, int width,
                                  int height) {
  SemanticView v;
  v.view = name;
  v.probabilities = std::move(blend);
  for (int p = 0; p < width * height; ++p) {
    float* d = v.pixel(p, classes);
    float alpha = 0;
    for (int j = 0; j < classes; ++j) alpha += d[j];
    const float rest = std::max(0.f, 1.f - alpha);
    for (int j = 0; j < classes; ++j) d[j] += rest * background[j];
  }
  set_argmax(v, classes, width, height);
  return v;
}

SemanticMaps render_semantic_maps(const GaussianModel& model,
                                  const std::vector<std::string>& instance_labels,
                                  const Capture& capture, const RenderSemanticsOptions& options,
                                  int* unknown) {
  if (model.instance_ids.size() != model.size())
    throw InputError("fusion.render_semantics: the model has " +
                     std::to_string(model.instance_ids.size()) + " instance ids for " +
                     std::to_string(model.size()) +
                     " Gaussians (segment it first, e.g. association.instance_mask_gaussian)");
  SemanticMaps out;
  out.classes = semantic_classes(capture, options.classes);
  const int classes = out.class_count();
  std::vector<int> instance_class;
  int unmatched = 0;
  for (const std::string& label : instance_labels) {
    instance_class.push_back(class_index(out.classes, label));
    if (instance_class.back() < 0) ++unmatched;
  }
  if (unknown) *unknown = unmatched;
  const std::vector<float> per_gaussian =
      gaussian_class_probabilities(model.instance_ids, instance_class, classes, options);
  const std::vector<float> background = background_distribution(classes, options);
  out.views.resize(capture.views.size());
  for (size_t v = 0; v < capture.views.size(); ++v) {
    const View& view = capture.views[v];
    RenderSettings settings;
    settings.rgb = false;  // only the blend weights
    const RenderCache cache(render(model, view.camera, view.pose, settings));
    out.views[v] = semantics_from_blend(view.name, cache.render(per_gaussian, classes), background,
                                        classes, view.camera.width, view.camera.height);
  }
  return out;
}

const ParamTable<RenderSemanticsOptions>& render_semantics_param_table() {
  using O = RenderSemanticsOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("instance_confidence", &O::instance_confidence,
               "probability an instance's Gaussians give its label's class", 0, 1)
          .add("background_confidence", &O::background_confidence,
               "probability unassigned Gaussians and the leftover transmittance give background", 0,
               1)
          .add("classes", &O::classes,
               "class vocabulary, ids 1..N (give the same to boxes.grabcut_priors); empty = the "
               "capture's ground-truth class names");
  return table;
}

}  // namespace gslift
