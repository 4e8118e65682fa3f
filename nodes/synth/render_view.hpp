// Ray-cast rendering of the embedded OR from one camera: RGB and exact ground truth (depth,
// normals, instance, semantic and part ids). One primary ray per pixel centre through the BVH,
// Lambert + ambient shading from point lights with optional hard shadows, procedural textures.
// Rows are rendered in parallel (tbb::parallel_for); every pixel depends only on its own ray, so
// the images are identical at any thread count.
#pragma once

#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"
#include "nodes/synth/bvh.hpp"
#include "nodes/synth/or_scene.hpp"

namespace gslift::synth {

struct RenderOptions {
  bool shadows = true;    // cast a shadow ray to each light (about 2.5x the cost of no shadows)
  float ambient = 0.35f;  // light reaching every surface (OR lighting is bright and diffuse)
};

struct RenderedView {
  cv::Mat rgb;       // CV_8UC3, RGB order
  cv::Mat depth;     // CV_32FC1 z-depth in metres (camera z of the hit point), 0 = no hit
  cv::Mat normal;    // CV_32FC3 world-space unit normal, flipped to face the camera
  cv::Mat instance;  // CV_32SC1 instance id, 0 = background (room)
  cv::Mat semantic;  // CV_32SC1 class id, 0 = background
  cv::Mat part;      // CV_32SC1 part of the instance (Primitive::part), 0 for the room
};

// World-space unit direction of the ray through the centre of pixel (u, v).
Eigen::Vector3f pixel_ray(const Camera& camera, const Pose& pose, int u, int v);

// A camera with distortion renders the image its lens records: each pixel centre's ray undistorted
// (opencv_camera.hpp), so depth stays the camera-frame z of the hit point.
RenderedView render_view(const OrScene& scene, const Bvh& bvh, const Camera& camera,
                         const Pose& pose, const RenderOptions& options);

}  // namespace gslift::synth
