// A view's answers registered to its photo (photo_alignment.hpp) [gslift addition, issue 28]: the
// params every node that renders answers in a view declares (inference.render_selection,
// inference.text_query), and the alignment of one view, found from the model's colours rendered
// at the view's written pose.
#pragma once

#include "nodes/inference/photo_alignment.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "param/param_table.hpp"

namespace gslift {

// Off by default; the graphs that turn it on say why (docs/saga.md, docs/langor.md).
struct MaskAlignment {
  bool to_photo = false;
  double min_gain = 0.003;
};

// align_to_photo, align_min_gain.
const ParamTable<MaskAlignment>& mask_alignment_param_table();

// The shift registering the model's colours rendered at `view` to its photo; not applied (a zero
// shift) when `align.to_photo` is off or the view has no photo.
PhotoAlignment view_photo_alignment(const GaussianModel& model, const View& view,
                                    const MaskAlignment& align);

}  // namespace gslift
