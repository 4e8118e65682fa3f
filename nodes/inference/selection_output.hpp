// What a promptable segmentation leaves behind (SAGA's render.py --target seg, and the export its
// users ask for): each selection rendered as a 2D mask in the views (accumulated alpha of the
// selected Gaussians >= 0.5, as SAGA thresholds its rendered 0/1 mask), and the selections as PLYs.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "nodes/inference/view_alignment.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/masks.hpp"

namespace gslift {

// model.instance_ids[g] = k: Gaussian g belongs to selection k, named names[k] (-1: none). One
// ViewMasks per view of `views`, one mask per selection, labelled with its name. With
// `align.to_photo`, each view with a photo renders the model's colours there and moves its masks
// by the shift that registers that render to the photo (when it passes min_gain); `alignments`
// (when given) receives one result per view, in the order of `views`.
MaskSet render_selection_masks(const GaussianModel& model, const Capture& capture,
                               const std::vector<int>& views, const std::vector<std::string>& names,
                               float threshold = 0.5f, const MaskAlignment& align = {},
                               std::vector<PhotoAlignment>* alignments = nullptr);

// Into `dir`: <view>__<name>_mask.png and _overlay.png for every mask (query_files.hpp), per
// selection <name>.ply (its Gaussians alone, plain INRIA layout: no features, no ids) and
// scene_selection.ply (every Gaussian, instance_id = its selection, -1 = none). Names are turned
// into file stems by query_file_stem.
void write_selection_files(const MaskSet& masks, const GaussianModel& model,
                           const std::vector<std::string>& names, const Capture& capture,
                           const std::filesystem::path& dir);

// The Gaussians of selection k as a model of their own, without features and ids.
GaussianModel selected_gaussians(const GaussianModel& model, int k);

}  // namespace gslift
