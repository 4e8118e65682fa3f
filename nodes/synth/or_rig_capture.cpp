#include "nodes/synth/or_rig_capture.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "base/atomic_file.hpp"
#include "nodes/ingest/view_files.hpp"
#include "nodes/scene/image_io.hpp"
#include "nodes/synth/bvh.hpp"
#include "nodes/synth/depth_prior_simulator.hpp"
#include "nodes/synth/drapes.hpp"
#include "nodes/synth/pose_noise.hpp"
#include "nodes/synth/render_view.hpp"
#include "nodes/synth/stream_purpose.hpp"

namespace gslift::synth {

namespace fs = std::filesystem;

namespace {

// One camera's frames, the same at every time step.
struct RigFrames {
  RenderedView colour;  // the captured (distorted) colour image and its ground truth
  RenderedView loaded;  // the pinhole image the reader undistorts it into, for the models
  cv::Mat depth;        // the depth camera's 16-bit-to-be depth prior, metres
};

}  // namespace

OrRigCamera rig_camera(const Camera& pinhole, const Pose& colour_pose) {
  OrRigCamera c;
  c.colour = pinhole;
  // k1 k2 p1 p2 k3 k4 k5 k6: about 7% barrel at half the image width, 15% in the corners.
  c.colour.distortion = {-0.18, 0.05, 0.0006, -0.0004, 0.0, 0.12, -0.02, 0.0};
  Camera depth;
  const double s = pinhole.width / 640.0;
  depth.width = std::max(8, static_cast<int>(std::lround(320 * s)));
  depth.height = std::max(8, static_cast<int>(std::lround(288 * s)));
  depth.fx = 0.47 * pinhole.fx;
  depth.fy = 0.47 * pinhole.fy;
  depth.cx = depth.width / 2.0 + 1.3;
  depth.cy = depth.height / 2.0 - 0.8;
  depth.distortion = {-0.06, 0.012, 0.0003, -0.0002, -0.001};
  c.depth = depth;
  c.depth_to_colour.R = (Eigen::AngleAxisd(1.5 * M_PI / 180, Eigen::Vector3d::UnitX()) *
                         Eigen::AngleAxisd(0.4 * M_PI / 180, Eigen::Vector3d::UnitY()))
                            .toRotationMatrix();
  c.depth_to_colour.t = {-0.032, -0.002, 0.004};
  c.colour_pose = colour_pose;
  return c;
}

std::string rig_camera_name(int index) {
  char name[32];
  std::snprintf(name, sizeof name, "camera%02d", index + 1);
  return name;
}

std::string rig_step_name(int step) {
  char name[32];
  std::snprintf(name, sizeof name, "%06d", step);
  return name;
}

void write_or_rig_recording(const OrCaptureSettings& s, const fs::path& out_dir, int time_steps,
                            RigDepth depth_kind) {
  if (time_steps < 1 || time_steps > 1000)
    throw std::invalid_argument("time steps: " + std::to_string(time_steps) +
                                " is not from 1 to 1000");
  // A rig writes millimetre depth TIFFs and metre calibrations, as the Azure Kinect does.
  if (s.knobs.world_scale != 1)
    throw std::invalid_argument(
        "world_scale: the rig layout is written in metres (world_scale 1 only)");
  OrScene scene = make_or_scene(s.scene);
  drape_equipment(scene, s.knobs.drapes, s.scene.seed);
  const Bvh bvh(scene.primitives);
  const int views = static_cast<int>(scene.cameras.size());
  std::vector<OrRigCamera> cameras;
  for (const OrCamera& c : scene.cameras) {
    cameras.push_back(rig_camera(c.camera, c.pose));
    if (depth_kind == RigDepth::registered) {
      cameras.back().depth.reset();
      cameras.back().depth_to_colour = Pose();
    }
  }
  write_folder_atomically(out_dir, [&](const fs::path& tmp) {
    std::vector<RigFrames> frames(views);
    tbb::parallel_for(0, views, [&](int i) {
      const OrRigCamera& rc = cameras[i];
      const Pose& pose = scene.cameras[i].pose;
      RenderOptions ro;
      ro.shadows = s.knobs.shadows;
      RigFrames& f = frames[i];
      f.colour = render_view(scene, bvh, rc.colour, pose, ro);
      // The pinhole the reader undistorts into: the colour camera without distortion, cropped.
      const cv::Rect r = undistorted_valid_rect(rc.colour);
      Camera loaded = rc.colour;
      loaded.distortion.clear();
      loaded.width = r.width;
      loaded.height = r.height;
      loaded.cx -= r.x;
      loaded.cy -= r.y;
      f.loaded = render_view(scene, bvh, loaded, pose, ro);
      // The depth camera: x_colour = R x_depth + t, so world -> depth is R^T (x_colour - t).
      // Registered depth: the colour camera itself, through its lens, at half its resolution.
      Pose depth_pose;
      depth_pose.R = rc.depth_to_colour.R.transpose() * pose.R;
      depth_pose.t = rc.depth_to_colour.R.transpose() * (pose.t - rc.depth_to_colour.t);
      const Camera depth_camera = rc.depth ? *rc.depth : rc.colour.scaled(0.5);
      RenderOptions plain;
      plain.shadows = false;  // only depth is kept
      const cv::Mat exact = render_view(scene, bvh, depth_camera, depth_pose, plain).depth;
      RandomStream depth_rng(stream_seed(s.scene.seed, kDepthPriorStream, i));
      f.depth = simulate_depth_prior(exact, s.knobs.depth_noise, s.knobs.depth_holes, depth_rng);
    });
    for (int i = 0; i < views; ++i) {
      OrRigCamera written = cameras[i];
      RandomStream pose_rng(stream_seed(s.scene.seed, kPoseNoiseStream, i));
      written.colour_pose =
          perturb_pose(written.colour_pose, s.knobs.pose_noise_deg, s.knobs.pose_noise_m, pose_rng);
      write_file_atomically(tmp / (rig_camera_name(i) + ".json"), or_rig_camera_json(written));
    }
    for (int t = 0; t < time_steps; ++t) {
      const std::string step = rig_step_name(t);
      const fs::path dir = tmp / step;
      for (int i = 0; i < views; ++i) {
        const std::string cam = rig_camera_name(i);
        const RigFrames& f = frames[i];
        write_rgb_png(dir / "colorimage" / (cam + "_colorimage-" + step + ".png"), f.colour.rgb);
        write_depth_png_mm(dir / "depthimage" / (cam + "_depthimage-" + step + ".tiff"), f.depth);
        write_ground_truth(f.colour, cam, dir);
        write_model_outputs(s, scene, i, f.loaded, cam, dir);
      }
      write_capture_files(s, scene, "rig: .\n", rig_camera_name, dir);
    }
  });
}

}  // namespace gslift::synth
