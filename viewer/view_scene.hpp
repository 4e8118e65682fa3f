// What `gslift view` shows: a Gaussian model (segmented, with per-Gaussian features, when the run
// made them), the capture it was reconstructed from, the name of each instance and the text
// encoder that answers queries, read from a run folder or from a PLY plus a capture.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/text_encoder.hpp"

namespace gslift {

struct ViewScene {
  std::string title;  // what was opened (the run folder or the PLY)
  GaussianModel model;
  Capture capture;
  // Per instance id of model.instance_ids: its label ("instance <k>" when the run named none).
  std::vector<std::string> instance_labels;
  // The run's text encoder (text.encoder, kinds lexical and hashing); null: no text queries.
  std::shared_ptr<const TextEncoder> encoder;
  // A run's metrics table (eval/metrics.md), shown beside the held-out views; empty without.
  std::string metrics_markdown;
  // The refined_poses.txt whose poses replaced the capture's (splat.reconstruct refine_poses: the
  // model was trained at those poses, so frames and clicks use them); empty: the written poses.
  std::string poses_file;
};

// A folder `gslift run` wrote: the model is the last node folder's (in the graph's order) that
// holds segmented.ply, else model.ply; the capture is what its ingest.capture node read (path as
// run.json records it, e.g. embedded:or), its poses those of a node folder's refined_poses.txt
// where the run refined them; labels come from an instances.json, the encoder from the
// text.encoder node's params. Throws InputError naming the folder or file that is missing or
// malformed.
ViewScene open_run_folder(const std::filesystem::path& run);

// A PLY (read_ply) and a capture (a folder or <scheme>:<spec>), its poses replaced by those of
// `poses_file` (a refined_poses.txt) when one is given; instances named by the capture's
// ground-truth classes when the PLY carries class ids, else "instance <k>".
ViewScene open_model(const std::filesystem::path& ply, const std::string& capture,
                     const std::filesystem::path& poses_file = {});

}  // namespace gslift
