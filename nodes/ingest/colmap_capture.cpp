#include "nodes/ingest/colmap_capture.hpp"

#include <spdlog/spdlog.h>

#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "nodes/ingest/colmap_model.hpp"

namespace gslift {

std::vector<ViewFiles> read_colmap_views(const std::filesystem::path& model_dir,
                                         const std::filesystem::path& images_dir,
                                         const CaptureOptions& options, SparsePoints& points) {
  // Each model file there: a regular file (not /dev/zero, a FIFO, a loop), inside the folder.
  for (const char* name : {"cameras", "images", "points3D"})
    for (const char* ext : {".bin", ".txt"}) {
      const std::filesystem::path file = model_dir / (std::string(name) + ext);
      if (!entry_exists(file)) continue;
      require_regular_file(file, "COLMAP model file");
      require_inside(model_dir, file, options.allow_outside_paths, "COLMAP model file");
    }
  ColmapModel model = read_colmap_model(model_dir);
  std::vector<ViewFiles> views;
  int skipped = 0;
  for (const auto& im : model.images) {
    const auto rgb = path_inside(images_dir, im.name, options.allow_outside_paths,
                                 model_dir.string() + " (image '" + im.name + "')");
    if (!std::filesystem::is_regular_file(rgb)) {
      if (!options.skip_missing_images)
        throw InputError(rgb.string() + ": image listed in the COLMAP model " + model_dir.string() +
                         " is missing (set skip_missing_images to leave such views out)");
      ++skipped;
      continue;
    }
    ViewFiles v;
    v.name = std::filesystem::path(im.name).replace_extension().generic_string();
    v.camera = model.cameras.at(im.camera_id);
    v.pose = im.pose;
    v.rgb = rgb;
    views.push_back(std::move(v));
  }
  if (skipped > 0)
    spdlog::warn("{}: skipped {} of {} images listed in the COLMAP model: not in {}",
                 model_dir.string(), skipped, model.images.size(), images_dir.string());
  points = std::move(model.points);
  return views;
}

}  // namespace gslift
