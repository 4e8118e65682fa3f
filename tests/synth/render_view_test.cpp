// The renderer's ground truth: instance ids agree across views, depth is the analytic distance,
// normals are unit and face the camera, semantic ids follow the instance -> class table.
#include <cmath>
#include <set>

#include "nodes/synth/bvh.hpp"
#include "nodes/synth/or_scene.hpp"
#include "nodes/synth/render_view.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using namespace gslift::synth;

namespace {

OrScene small_scene(uint64_t seed, OrPhase phase = OrPhase::Surgery) {
  OrSceneOptions o;
  o.seed = seed;
  o.phase = phase;
  o.width = 160;
  o.height = 120;
  return make_or_scene(o);
}

}  // namespace

TEST_CASE("a 3D point visible in two views carries the same instance id in both") {
  for (uint64_t seed : {0u, 7u}) {
    const OrScene scene = small_scene(seed);
    const Bvh bvh(scene.primitives);
    std::vector<RenderedView> views;
    for (const OrCamera& c : scene.cameras) {
      views.push_back(render_view(scene, bvh, c.camera, c.pose, RenderOptions{}));
    }
    int checked = 0, agree = 0, objects = 0;
    for (size_t a = 0; a < views.size(); ++a) {
      const OrCamera& ca = scene.cameras[a];
      for (size_t b = 0; b < views.size(); ++b) {
        if (a == b) continue;
        const OrCamera& cb = scene.cameras[b];
        for (int v = 0; v < ca.camera.height; v += 3) {
          for (int u = 0; u < ca.camera.width; u += 3) {
            const float d = views[a].depth.at<float>(v, u);
            if (d <= 0) continue;
            const Eigen::Vector3d ray((u + 0.5 - ca.camera.cx) / ca.camera.fx,
                                      (v + 0.5 - ca.camera.cy) / ca.camera.fy, 1.0);
            const Eigen::Vector3d x = ca.pose.centre() + ca.pose.R.transpose() * ray * d;
            const Eigen::Vector3d xb = cb.pose.to_camera(x);
            if (xb.z() <= 0) continue;
            const int ub =
                static_cast<int>(std::floor(cb.camera.fx * xb.x() / xb.z() + cb.camera.cx));
            const int vb =
                static_cast<int>(std::floor(cb.camera.fy * xb.y() / xb.z() + cb.camera.cy));
            if (ub < 0 || vb < 0 || ub >= cb.camera.width || vb >= cb.camera.height) continue;
            // Visible in B only where B's depth agrees (otherwise something occludes it).
            if (std::abs(views[b].depth.at<float>(vb, ub) - xb.z()) > 0.01 * xb.z()) continue;
            ++checked;
            const int ida = views[a].instance.at<int>(v, u);
            objects += ida != 0;
            agree += ida == views[b].instance.at<int>(vb, ub);
          }
        }
      }
    }
    INFO("seed " << seed << ": " << agree << " of " << checked << " agree");
    CHECK(checked > 5000);
    CHECK(objects > 1000);  // the check covers entities, not only the room
    CHECK(agree >= 0.99 * checked);
  }
}

TEST_CASE("depth is the analytic z-distance to a sphere and to the floor") {
  OrScene scene;
  Primitive sphere;
  sphere.shape = Shape::Sphere;
  sphere.centre = Eigen::Vector3f(0, 0, 1);
  sphere.half_extents = Eigen::Vector3f::Constant(0.5f);
  sphere.instance = 1;
  Primitive floor;
  floor.shape = Shape::Box;
  floor.centre = Eigen::Vector3f(0, 0, -0.1f);
  floor.half_extents = Eigen::Vector3f(10, 10, 0.1f);
  scene.primitives = {sphere, floor};
  scene.lights = {{Eigen::Vector3f(0, 0, 3), 0.5f}};
  Camera cam;
  cam.width = 80, cam.height = 60, cam.fx = cam.fy = 60, cam.cx = 40, cam.cy = 30;
  // Camera at (3, 0, 1.5) looking at the sphere centre, z up.
  const Eigen::Vector3d c(3, 0, 1.5), f = (Eigen::Vector3d(0, 0, 1) - c).normalized();
  const Eigen::Vector3d right = f.cross(Eigen::Vector3d::UnitZ()).normalized();
  Pose pose;
  pose.R.row(0) = right;
  pose.R.row(1) = f.cross(right);
  pose.R.row(2) = f;
  pose.t = -pose.R * c;
  const Bvh bvh(scene.primitives);
  const RenderedView r = render_view(scene, bvh, cam, pose, RenderOptions{});
  int sphere_px = 0, floor_px = 0;
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      const Eigen::Vector3d dir =
          pose.R.transpose() *
          Eigen::Vector3d((u + 0.5 - cam.cx) / cam.fx, (v + 0.5 - cam.cy) / cam.fy, 1).normalized();
      // Sphere: |c + t dir - s|^2 = r^2.
      const Eigen::Vector3d oc = c - Eigen::Vector3d(0, 0, 1);
      const double b = oc.dot(dir), disc = b * b - (oc.squaredNorm() - 0.25);
      double t = disc >= 0 ? -b - std::sqrt(disc) : -1;
      int id = 1;
      if (t <= 0) t = dir.z() < 0 ? -c.z() / dir.z() : -1, id = 0;  // floor plane z = 0
      if (t <= 0) continue;
      const Eigen::Vector3d p = c + t * dir;
      if (id == 0 && (std::abs(p.x()) > 9.9 || std::abs(p.y()) > 9.9)) continue;  // off the floor
      // Grazing rays at the silhouette may round either way; skip them.
      if (id == 1 && disc < 1e-3) continue;
      const double z = t * dir.dot(f);
      REQUIRE(r.instance.at<int>(v, u) == id);
      CHECK(r.depth.at<float>(v, u) == Approx(z).epsilon(1e-4));
      (id ? sphere_px : floor_px)++;
    }
  }
  CHECK(sphere_px > 200);
  CHECK(floor_px > 200);
}

TEST_CASE("normals are unit and face the camera, semantic ids follow the instance classes") {
  const OrScene scene = small_scene(3, OrPhase::Closing);
  const Bvh bvh(scene.primitives);
  for (const OrCamera& c : scene.cameras) {
    const RenderedView r = render_view(scene, bvh, c.camera, c.pose, RenderOptions{});
    int bad_norm = 0, back_facing = 0, bad_class = 0, hits = 0;
    for (int v = 0; v < c.camera.height; ++v) {
      for (int u = 0; u < c.camera.width; ++u) {
        if (r.depth.at<float>(v, u) <= 0) continue;
        ++hits;
        const cv::Vec3f n = r.normal.at<cv::Vec3f>(v, u);
        const Eigen::Vector3f ne(n[0], n[1], n[2]);
        bad_norm += std::abs(ne.norm() - 1.f) > 1e-4f;
        back_facing += ne.dot(pixel_ray(c.camera, c.pose, u, v)) > 0;
        const int inst = r.instance.at<int>(v, u), sem = r.semantic.at<int>(v, u);
        bad_class += inst == 0 ? sem != 0 : sem != scene.instance_class.at(inst);
      }
    }
    CHECK(hits == c.camera.width * c.camera.height);  // a closed room: every ray hits
    CHECK(bad_norm == 0);
    CHECK(back_facing == 0);
    CHECK(bad_class == 0);
  }
}

TEST_CASE("every class appears in the scene and every view sees the table") {
  for (OrPhase phase : {OrPhase::Preparation, OrPhase::Surgery, OrPhase::Closing}) {
    const OrScene scene = small_scene(11, phase);
    std::set<int> classes;
    for (const auto& [inst, cls] : scene.instance_class) classes.insert(cls);
    CHECK(classes.size() == static_cast<size_t>(kOrClassCount));
    const Bvh bvh(scene.primitives);
    for (const OrCamera& c : scene.cameras) {
      const RenderedView r = render_view(scene, bvh, c.camera, c.pose, RenderOptions{});
      CHECK(cv::countNonZero(r.semantic == kOperatingTable) > 20);
    }
  }
}

namespace {

// Mean centre of an instance's primitives, in the floor plane.
Eigen::Vector2f floor_position(const OrScene& scene, int class_id) {
  Eigen::Vector2f sum = Eigen::Vector2f::Zero();
  int n = 0;
  for (const Primitive& p : scene.primitives) {
    if (p.semantic != class_id) continue;
    sum += p.centre.head<2>();
    ++n;
  }
  return sum / std::max(n, 1);
}

}  // namespace

TEST_CASE("the phase moves the surgeons and the C-arm, the seed changes the layout") {
  for (uint64_t seed = 0; seed < 6; ++seed) {
    const OrScene prep = small_scene(seed, OrPhase::Preparation);
    const OrScene surgery = small_scene(seed, OrPhase::Surgery);
    const Eigen::Vector2f table = surgery.look_at.head<2>();
    for (int role : {kHeadSurgeon, kAssistantSurgeon}) {
      // Standing at the table while operating, a step back while preparing.
      const float d_surgery = (floor_position(surgery, role) - table).norm();
      const float d_prep = (floor_position(prep, role) - table).norm();
      CHECK(d_surgery < 1.0f);
      CHECK(d_prep > d_surgery + 0.2f);
    }
    CHECK((floor_position(surgery, kCArm) - table).norm() <
          (floor_position(prep, kCArm) - table).norm());
    // The anaesthetist works at the head end (+x) of the table, next to the machine.
    CHECK(floor_position(surgery, kAnaesthetist).x() > table.x() + 1.0f);
    const OrScene other = small_scene(seed + 100, OrPhase::Surgery);
    CHECK((floor_position(other, kHeadSurgeon) - floor_position(surgery, kHeadSurgeon)).norm() >
          1e-3f);
  }
}
