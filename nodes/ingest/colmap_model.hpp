// COLMAP sparse models (cameras, images, points3D) in text and binary form, as COLMAP writes
// them (colmap/src/colmap/scene/reconstruction_io.cc). The synthetic generator writes text
// models with write_colmap_text; ingest reads either.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/capture.hpp"

namespace gslift {

struct ColmapImage {
  int id = 0;
  int camera_id = 0;
  std::string name;  // path relative to the images folder, e.g. "000000.png"
  Pose pose;         // world -> camera
};

struct ColmapModel {
  std::map<int, Camera> cameras;    // by camera id
  std::vector<ColmapImage> images;  // sorted by name, so text and binary models list views alike
  SparsePoints points;
};

// Reads <folder>/{cameras,images,points3D}.{bin,txt}; the binary files win when both exist.
// Missing files, truncated binaries, non-numeric fields, unknown camera models and images that
// refer to absent cameras are InputErrors naming the file. points3D may be absent (no points).
ColmapModel read_colmap_model(const std::filesystem::path& folder);
ColmapModel read_colmap_text(const std::filesystem::path& folder);
ColmapModel read_colmap_binary(const std::filesystem::path& folder);

// Writes cameras.txt, images.txt and points3D.txt into folder (created if needed), with the
// classic locale and 17 significant digits so doubles round-trip exactly. Cameras without
// distortion are PINHOLE, with 4 coefficients OPENCV, with 5 or 8 FULL_OPENCV (5: k4..k6 = 0).
void write_colmap_text(const std::filesystem::path& folder, const ColmapModel& model);

}  // namespace gslift
