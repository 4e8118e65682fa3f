#include "nodes/fusion/render_semantics.hpp"

#include <algorithm>

#include "base/errors.hpp"

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

const ParamTable<RenderSemanticsOptions>& render_semantics_param_table() {
  using O = RenderSemanticsOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("instance_confidence", &O::instance_confidence,
               "probability an instance's Gaussians give its label's class", 0, 1)
          .add("background_confidence", &O::background_confidence,
               "probability unassigned Gaussians and the leftover transmittance give background", 0,
               1);
  return table;
}

}  // namespace gslift
