// 3D post-processing of segmented Gaussians (SAGA's 3D post-processing; shared by every
// method that labels Gaussians). A 2D-supervised selection keeps floaters far from the object and
// misses parts that no training view separated; three steps on the Gaussian centres clean it:
//  1. statistical outlier filter: k = sqrt(n) nearest neighbours within the instance; a Gaussian
//     whose mean neighbour distance exceeds mu + std_ratio * sigma (over the instance) is dropped;
//  2. connected components of the kept Gaussians, two being linked when closer than r, the largest
//     nearest-neighbour distance in the filtered set: components holding the instance's mass are
//     kept (the largest, and any other with at least `min_component_fraction` of its Gaussians);
//  3. ball-query growth: a Gaussian within r of the kept set joins the instance, when it was
//     unassigned or removed from this same instance by steps 1-2, and is not excluded from it
//     (an instance's exclusion: the Gaussians its prompt's 2D answers rule out,
//     growth_exclusion.hpp).
// Gaussians removed from an instance and not restored become unassigned (-1), never another
// instance's.
// Growth has no feature or colour check (SAGA's neither), so a selection that touches a dense
// surface can grow into the floor, the walls or the table under a DTU object: a 10k-Gaussian
// selection grown by 21k into the whole view (issue 28). Growth of an instance is therefore
// refused, keeping its un-grown Gaussians, when it would leave the instance more than
// max_growth_ratio times its un-grown size or more than max_scene_fraction of the scene.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "param/param_table.hpp"

namespace gslift {

struct Filter3dOptions {
  bool statistical = true;
  double std_ratio = 1.0;  // SAGA: mu + sigma
  bool components = true;
  // A component other than the largest is kept when it holds at least this fraction of the
  // instance's filtered Gaussians [decision: a second piece of one object, e.g. a table's far
  // edge behind a person, is kept; a speck of floaters is not].
  double min_component_fraction = 0.2;
  bool grow = true;
  // Instances with fewer Gaussians than this are left as they are: sqrt(n) neighbours and a
  // mean / std over a handful of points say nothing.
  int min_instance_size = 8;
  // Growth reaches only Gaussians inside the kept set's axis-aligned box widened by this
  // fraction of its extent per side (SAGA's notebook crops to the seeds' box + 5% before its ball
  // query: what bounds its growth there); negative = no box [off by default: docs/saga.md].
  double growth_box_margin = -1;
  // Growth of an instance is refused when afterwards it would hold more than this many times its
  // Gaussians before growth (after steps 1-2); 0 = no bound [off by default: 3 gained 0.8 mIoU on
  // two OR dev rooms and cost 18 points on DTU's test capture, where the refused 3.3x growth
  // was what filled the object: docs/saga.md, "Dev and test"].
  double max_growth_ratio = 0;
  // ... or more than this fraction of all the scene's Gaussians [decision, dev set]; 1 = no bound.
  double max_scene_fraction = 1.0;
  // Growth that stops at feature discontinuities (issue 28): a Gaussian joins an instance only
  // when the cosine similarity of its feature to the instance's prototype (the normalised mean of
  // its kept Gaussians' normalised features) reaches this; -1 = no check, SAGA's ball query.
  double growth_min_similarity = -1;
};

const ParamTable<Filter3dOptions>& filter_3d_param_table();

struct Filter3dResult {
  std::vector<int32_t> instance_ids;  // per Gaussian, -1 = unassigned
  int64_t outliers = 0;               // removed by the statistical filter
  int64_t component_dropped = 0;      // removed with a small connected component
  int64_t grown = 0;                  // unassigned Gaussians that joined an instance
  int64_t restored = 0;               // removed by steps 1-2, then within r of the kept set
  int64_t excluded = 0;               // within reach of an instance's growth, but excluded from it
  // Per instance (filtered ones, in id order): Gaussians on input, after steps 1-2, and at the
  // end; refused = its growth exceeded a bound and was undone (after == kept).
  struct Growth {
    int32_t id = -1;
    int64_t input = 0, kept = 0, after = 0;
    int64_t would_be = 0;  // what growth would have made it (== after unless refused)
    bool refused = false;
  };
  std::vector<Growth> growth;
  int64_t refused = 0;  // instances whose growth was refused
};

// Per instance id, per Gaussian: 1 = may not join that instance by growth.
using GrowthExclusion = std::map<int32_t, std::vector<char>>;

// means: N x 3 centres (row-major); instance_ids: N ids, -1 = unassigned; features: N x
// feature_dim (row-major), needed only for growth_min_similarity; excluded: N flags per listed
// instance. Deterministic at any thread count. Throws std::invalid_argument on inconsistent
// sizes, or a similarity gate without features.
Filter3dResult filter_instances_3d(const std::vector<float>& means,
                                   const std::vector<int32_t>& instance_ids,
                                   const Filter3dOptions& options,
                                   const std::vector<float>& features = {}, int feature_dim = 0,
                                   const GrowthExclusion& excluded = {});

}  // namespace gslift
