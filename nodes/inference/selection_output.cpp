#include "nodes/inference/selection_output.hpp"

#include <algorithm>

#include "base/errors.hpp"
#include "nodes/inference/query_files.hpp"
#include "nodes/inference/text_query.hpp"
#include "nodes/splat/ply_io.hpp"

namespace gslift {

MaskSet render_selection_masks(const GaussianModel& model, const Capture& capture,
                               const std::vector<int>& views, const std::vector<std::string>& names,
                               float threshold, const MaskAlignment& align,
                               std::vector<PhotoAlignment>* alignments) {
  if (model.instance_ids.size() != model.size())
    throw InputError("selection masks: the model has no selection (instance ids)");
  MaskSet out;
  if (alignments) alignments->clear();
  for (int v : views) {
    const View& view = capture.views[v];
    const QueryView qv(model, view.camera, view.pose);
    const PhotoAlignment alignment = view_photo_alignment(model, view, align);
    if (alignments) alignments->push_back(alignment);
    ViewMasks vm{view.name, {}};
    for (size_t k = 0; k < names.size(); ++k) {
      Mask m;
      m.pixels = align_image(qv.instance_mask({static_cast<int>(k)}, threshold), alignment);
      m.label = names[k];
      vm.masks.push_back(std::move(m));
    }
    out.views.push_back(std::move(vm));
  }
  return out;
}

GaussianModel selected_gaussians(const GaussianModel& model, int k) {
  std::vector<size_t> rows;
  for (size_t g = 0; g < model.instance_ids.size(); ++g)
    if (model.instance_ids[g] == k) rows.push_back(g);
  GaussianModel out = model.subset(rows);
  out.feature_dim = 0;
  out.features.clear();
  out.instance_ids.clear();
  out.class_ids.clear();
  return out;
}

void write_selection_files(const MaskSet& masks, const GaussianModel& model,
                           const std::vector<std::string>& names, const Capture& capture,
                           const std::filesystem::path& dir) {
  for (const ViewMasks& vm : masks.views) {
    const int vi = capture.find_view(vm.view);
    const cv::Mat rgb =
        vi >= 0 && capture.views[vi].rgb.present() ? capture.views[vi].rgb.load() : cv::Mat();
    for (const Mask& m : vm.masks)
      write_mask_files(dir, vm.view + "__" + query_file_stem(m.label), m.pixels, rgb, m.label);
  }
  for (size_t k = 0; k < names.size(); ++k)
    write_ply(selected_gaussians(model, static_cast<int>(k)),
              dir / (query_file_stem(names[k]) + ".ply"));
  GaussianModel scene = model;
  scene.features.clear();
  scene.feature_dim = 0;
  write_ply(scene, dir / "scene_selection.ply");
}

}  // namespace gslift
