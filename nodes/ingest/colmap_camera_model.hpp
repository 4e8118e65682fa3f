// COLMAP camera models (colmap/src/colmap/sensor/models.h) and their mapping to Camera, whose
// distortion is OpenCV's (k1, k2, p1, p2[, k3[, k4, k5, k6]]).
#pragma once

#include <string>
#include <vector>

#include "nodes/scene/camera.hpp"

namespace gslift {

// The models gslift reads, with COLMAP's ids and parameter counts:
//   0 SIMPLE_PINHOLE f cx cy            1 PINHOLE fx fy cx cy
//   2 SIMPLE_RADIAL  f cx cy k          3 RADIAL  f cx cy k1 k2
//   4 OPENCV fx fy cx cy k1 k2 p1 p2    6 FULL_OPENCV fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6
// FULL_OPENCV is OpenCV's rational model: 8 coefficients, or 5 when k4 = k5 = k6 = 0.
struct ColmapCameraModel {
  int id;
  const char* name;
  int num_params;
};

// Looks a model up by id or name; throws InputError mentioning `where` and the supported models
// when it is unknown.
const ColmapCameraModel& colmap_camera_model(int id, const std::string& where);
const ColmapCameraModel& colmap_camera_model(const std::string& name, const std::string& where);

// Builds a Camera from a model's parameters (params.size() must equal model.num_params).
Camera camera_from_colmap(const ColmapCameraModel& model, int width, int height,
                          const std::vector<double>& params, const std::string& where);

// The model name and parameters that write `camera` exactly (PINHOLE, OPENCV or FULL_OPENCV).
// Throws std::invalid_argument for the thin-prism model (12 coefficients), which COLMAP's
// perspective models lack.
std::pair<std::string, std::vector<double>> colmap_params_of(const Camera& camera);

}  // namespace gslift
