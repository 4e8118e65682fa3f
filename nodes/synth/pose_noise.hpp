// Pose errors of an SfM/MVS estimate: the images are rendered from the exact poses, the capture
// records perturbed ones, so reconstruction sees the misregistration a real pipeline would.
#pragma once

#include "nodes/scene/camera.hpp"
#include "nodes/synth/stream_purpose.hpp"

namespace gslift::synth {

// Rotates the camera by a random axis and an angle ~ N(0, rotation_deg) and moves its centre by
// N(0, translation_m) per axis. Zero sigmas return the pose unchanged.
Pose perturb_pose(const Pose& pose, double rotation_deg, double translation_m, RandomStream& rng);

}  // namespace gslift::synth
