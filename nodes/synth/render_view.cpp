#include "nodes/synth/render_view.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "nodes/ingest/opencv_camera.hpp"
#include "nodes/synth/stream_purpose.hpp"

namespace gslift::synth {

namespace {

using Vec3 = Eigen::Vector3f;

// Deterministic lattice value in [0, 1) for integer coordinates.
float lattice(int x, int y, int z) {
  const uint64_t h = splitmix64((static_cast<uint64_t>(static_cast<uint32_t>(x)) << 42) ^
                                (static_cast<uint64_t>(static_cast<uint32_t>(y)) << 21) ^
                                static_cast<uint32_t>(z));
  return static_cast<float>(h >> 40) * (1.f / 16777216.f);
}

// Trilinear value noise in [0, 1): cheap fabric-like variation without stored textures.
float value_noise(const Vec3& p) {
  const Vec3 f = p.array().floor();
  const int x = static_cast<int>(f.x()), y = static_cast<int>(f.y()), z = static_cast<int>(f.z());
  const Vec3 w = p - f;
  auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
  const float x00 = lerp(lattice(x, y, z), lattice(x + 1, y, z), w.x());
  const float x10 = lerp(lattice(x, y + 1, z), lattice(x + 1, y + 1, z), w.x());
  const float x01 = lerp(lattice(x, y, z + 1), lattice(x + 1, y, z + 1), w.x());
  const float x11 = lerp(lattice(x, y + 1, z + 1), lattice(x + 1, y + 1, z + 1), w.x());
  return lerp(lerp(x00, x10, w.y()), lerp(x01, x11, w.y()), w.z());
}

Vec3 albedo_at(const Material& m, const Vec3& p) {
  switch (m.texture) {
    case Texture::Flat:
      return m.albedo;
    case Texture::Fabric:
      return m.albedo * (0.82f + 0.18f * value_noise(p * 60.f));
    case Texture::Speckle:
      return m.albedo * (0.92f + 0.08f * value_noise(p * 200.f));
    case Texture::Tiles: {
      // 0.4 m tiles with 1.2 cm grout; each tile a slightly different shade.
      constexpr float kTile = 0.4f, kGrout = 0.012f;
      const float fx = p.x() / kTile - std::floor(p.x() / kTile);
      const float fy = p.y() / kTile - std::floor(p.y() / kTile);
      if (fx * kTile < kGrout || fy * kTile < kGrout) return m.albedo * 0.55f;
      const float shade = lattice(static_cast<int>(std::floor(p.x() / kTile)),
                                  static_cast<int>(std::floor(p.y() / kTile)), 7);
      return m.albedo * (0.9f + 0.1f * shade);
    }
  }
  return m.albedo;
}

}  // namespace

Vec3 pixel_ray(const Camera& camera, const Pose& pose, int u, int v) {
  const Vec3 d_cam(static_cast<float>((u + 0.5 - camera.cx) / camera.fx),
                   static_cast<float>((v + 0.5 - camera.cy) / camera.fy), 1.f);
  return (pose.R.transpose().cast<float>() * d_cam).normalized();
}

RenderedView render_view(const OrScene& scene, const Bvh& bvh, const Camera& camera,
                         const Pose& pose, const RenderOptions& options) {
  const int w = camera.width, h = camera.height;
  RenderedView out;
  out.rgb = cv::Mat(h, w, CV_8UC3, cv::Scalar::all(0));
  out.depth = cv::Mat(h, w, CV_32FC1, cv::Scalar(0));
  out.normal = cv::Mat(h, w, CV_32FC3, cv::Scalar::all(0));
  out.instance = cv::Mat(h, w, CV_32SC1, cv::Scalar(0));
  out.semantic = cv::Mat(h, w, CV_32SC1, cv::Scalar(0));
  out.part = cv::Mat(h, w, CV_32SC1, cv::Scalar(0));
  const Vec3 origin = pose.centre().cast<float>();
  const Vec3 forward = pose.R.row(2).transpose().cast<float>();
  constexpr float kFar = 100.f, kEpsilon = 1e-4f;
  // Through a lens with distortion each pixel centre sees along its undistorted ray.
  std::vector<cv::Point2d> rays;
  if (!camera.distortion.empty()) {
    std::vector<cv::Point2d> centres;
    centres.reserve(static_cast<size_t>(w) * h);
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) centres.push_back({u + 0.5, v + 0.5});
    rays = pixel_rays(camera, centres);
  }
  const Eigen::Matrix3f to_world = pose.R.transpose().cast<float>();

  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v) {
      for (int u = 0; u < w; ++u) {
        const cv::Point2d* ray = rays.empty() ? nullptr : &rays[static_cast<size_t>(v) * w + u];
        const Vec3 dir =
            ray ? (to_world * Vec3(static_cast<float>(ray->x), static_cast<float>(ray->y), 1.f))
                      .normalized()
                : pixel_ray(camera, pose, u, v);
        const RayHit rh = bvh.closest(origin, dir, kEpsilon, kFar);
        if (rh.primitive < 0) continue;
        const Primitive& prim = scene.primitives[rh.primitive];
        Vec3 n = rh.hit.normal;
        if (n.dot(dir) > 0) n = -n;  // face the camera (thin or entered surfaces)
        const Vec3 p = origin + rh.hit.t * dir;
        float shade = options.ambient;
        for (const PointLight& light : scene.lights) {
          Vec3 to_light = light.position - p;
          const float dist = to_light.norm();
          to_light /= dist;
          const float lambert = n.dot(to_light);
          if (lambert <= 0) continue;
          // Offset along the normal so the shadow ray does not hit its own surface.
          if (options.shadows && bvh.occluded(p + 1e-3f * n, to_light, kEpsilon, dist)) continue;
          shade += light.intensity * lambert;
        }
        const Vec3 c = (albedo_at(prim.material, p) * shade).cwiseMin(1.f).cwiseMax(0.f);
        out.rgb.at<cv::Vec3b>(v, u) = cv::Vec3b(static_cast<uint8_t>(std::lround(c.x() * 255)),
                                                static_cast<uint8_t>(std::lround(c.y() * 255)),
                                                static_cast<uint8_t>(std::lround(c.z() * 255)));
        out.depth.at<float>(v, u) = rh.hit.t * dir.dot(forward);
        out.normal.at<cv::Vec3f>(v, u) = cv::Vec3f(n.x(), n.y(), n.z());
        out.instance.at<int>(v, u) = prim.instance;
        out.semantic.at<int>(v, u) = prim.semantic;
        out.part.at<int>(v, u) = prim.part;
      }
    }
  });
  return out;
}

}  // namespace gslift::synth
