// Views of a COLMAP workspace: a sparse model folder and the folder its image names are
// relative to.
#pragma once

#include <filesystem>
#include <vector>

#include "nodes/ingest/capture_options.hpp"
#include "nodes/ingest/view_files.hpp"

namespace gslift {

// One ViewFiles per model image, in name order, with the model's sparse points in `points`.
// An image missing from images_dir is an InputError naming it, unless
// options.skip_missing_images (then it is left out with a warning).
std::vector<ViewFiles> read_colmap_views(const std::filesystem::path& model_dir,
                                         const std::filesystem::path& images_dir,
                                         const CaptureOptions& options, SparsePoints& points);

}  // namespace gslift
