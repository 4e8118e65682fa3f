// Geometric automatic masks on a ray-cast depth map whose surfaces are known (a floor, a box on it
// and a sphere above it), on empty and malformed depth, and on a real RGB-D capture.
#include "nodes/masks/geometry_masks.hpp"

#include <cmath>
#include <optional>

#include <Eigen/Core>

#include "base/errors.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// What a pixel of the ray-cast scene shows.
enum SceneSurface : uchar { kFloor = 1, kBox = 2, kBoxTop = 3, kSphere = 4 };

struct RayCastScene {
  Camera camera;
  cv::Mat1f depth;  // camera z of the nearest hit
  cv::Mat1b surface;
};

// A 320x240 pinhole camera 1.5 m above the floor (world y up), looking 30 degrees down along +z,
// at a 0.6 m box standing on the floor (x -0.9..-0.3, z 2.4..3.0, 0.5 m high) and a sphere of
// radius 0.3 m floating 0.1 m above it (centre x 0.5, y 0.4, z 2.7).
RayCastScene ray_cast_scene() {
  RayCastScene s;
  s.camera.width = 320;
  s.camera.height = 240;
  s.camera.fx = s.camera.fy = 240;
  s.camera.cx = 160;
  s.camera.cy = 120;
  const double c = std::cos(30 * M_PI / 180), sn = std::sin(30 * M_PI / 180);
  const Eigen::Vector3d centre(0, 1.5, 0), forward(0, -sn, c), down(0, -c, -sn),
      right = down.cross(forward);
  const Eigen::Vector3d box_lo(-0.9, 0, 2.4), box_hi(-0.3, 0.5, 3.0), ball(0.5, 0.4, 2.7);
  const double radius = 0.3;
  s.depth = cv::Mat1f(240, 320, 0.f);
  s.surface = cv::Mat1b(240, 320, uchar(0));
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x) {
      // The ray's camera z is 1, so the hit's parameter t is its depth.
      const Eigen::Vector3d d =
          right * ((x + 0.5 - 160) / 240) + down * ((y + 0.5 - 120) / 240) + forward;
      double best = 1e9;
      uchar what = 0;
      if (d.y() < 0) best = -centre.y() / d.y(), what = kFloor;
      // Box: slabs.
      double t0 = 0, t1 = 1e9;
      int axis = -1;
      for (int a = 0; a < 3; ++a) {
        double ta = (box_lo[a] - centre[a]) / d[a], tb = (box_hi[a] - centre[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        if (ta > t0) t0 = ta, axis = a;
        t1 = std::min(t1, tb);
      }
      if (t0 < t1 && t0 < best) best = t0, what = axis == 1 ? kBoxTop : kBox;
      // Sphere.
      const Eigen::Vector3d oc = centre - ball;
      const double b = oc.dot(d), cc = oc.squaredNorm() - radius * radius, a2 = d.squaredNorm();
      const double disc = b * b - a2 * cc;
      if (disc > 0) {
        const double t = (-b - std::sqrt(disc)) / a2;
        if (t > 0 && t < best) best = t, what = kSphere;
      }
      if (what) s.depth(y, x) = static_cast<float>(best), s.surface(y, x) = what;
    }
  return s;
}

double granularity_best_iou(const std::vector<Mask>& masks, const cv::Mat1b& target,
                            int granularity) {
  double best = 0;
  for (const Mask& m : masks)
    if (m.granularity == granularity) best = std::max(best, mask_iou(m.pixels, target));
  return best;
}

// The options for the test scene's view: its floor covers 93% of it, above the 90% beyond which
// the defaults drop a segment as saying nothing about its parts.
GeometryMaskOptions scene_options() {
  GeometryMaskOptions o;
  o.keep.max_area_fraction = 0.95;
  return o;
}

}  // namespace

TEST_CASE(
    "geometry masks: the floor is a plane, the box and the sphere objects, the box's faces "
    "its parts") {
  const RayCastScene s = ray_cast_scene();
  const cv::Mat1b floor = s.surface == kFloor, sphere = s.surface == kSphere;
  const cv::Mat1b box = (s.surface == kBox) | (s.surface == kBoxTop), top = s.surface == kBoxTop;
  REQUIRE(cv::countNonZero(box) > 2400);  // the scene shows what the test is about
  REQUIRE(cv::countNonZero(sphere) > 1600);
  REQUIRE(cv::countNonZero(top) > 600);
  const GeometryMaskOptions o = scene_options();
  const GeometrySegments seg = geometry_segments(s.depth, s.camera, o);
  REQUIRE(seg.labels.size() == 3);

  // One dominant plane, the floor; the box's faces are too small to be one.
  CHECK(seg.plane_count == 1);
  CHECK(mask_iou(seg.planes > 0, floor) > 0.95);

  const std::vector<Mask> masks = geometry_masks(s.depth, s.camera, o);
  // Groups (0) and objects (1): the floor, the box, the sphere, each one mask. The sphere floats
  // (a depth discontinuity), the box stands on the floor (a concave crease, and the plane).
  for (int g : {0, 1}) {
    INFO("granularity " << g);
    CHECK(granularity_best_iou(masks, floor, g) > 0.95);
    CHECK(granularity_best_iou(masks, box, g) > 0.9);
    CHECK(granularity_best_iou(masks, sphere, g) > 0.9);
  }
  // Parts (2): the box's convex edges cut it into faces (its top alone), the smooth sphere stays
  // whole.
  CHECK(granularity_best_iou(masks, box, 2) < 0.7);
  CHECK(granularity_best_iou(masks, top, 2) > 0.8);
  CHECK(granularity_best_iou(masks, sphere, 2) > 0.9);

  // Discontinuity edges separate the surfaces at every granularity: no segment that becomes a
  // mask holds pixels of two of them (a few pixels along an edge may go either way).
  for (const cv::Mat1i& labels : seg.labels) {
    double top_id = 0;
    cv::minMaxLoc(labels, nullptr, &top_id);
    for (int id = 0; id <= top_id; ++id) {
      const cv::Mat1b segment = labels == id;
      const int area = cv::countNonZero(segment);
      if (area < o.keep.min_area) continue;
      int most = 0;
      for (const cv::Mat1b& truth : {floor, box, sphere})
        most = std::max(most, cv::countNonZero(segment & truth));
      CHECK(most >= 0.97 * area);
    }
  }

  // The granularities nest: every segment of g + 1 lies inside one segment of g.
  for (int g = 0; g + 1 < 3; ++g) {
    std::map<int, int> parent;
    bool nested = true;
    for (int i = 0; i < static_cast<int>(s.depth.total()); ++i) {
      const int child = seg.labels[g + 1](i), coarse = seg.labels[g](i);
      if (child < 0) continue;
      auto [it, fresh] = parent.emplace(child, coarse);
      if (!fresh && it->second != coarse) nested = false;
    }
    CHECK(nested);
  }

  // Deterministic.
  const std::vector<Mask> again = geometry_masks(s.depth, s.camera, o);
  REQUIRE(again.size() == masks.size());
  for (size_t k = 0; k < masks.size(); ++k)
    CHECK(cv::countNonZero(masks[k].pixels != again[k].pixels) == 0);
}

TEST_CASE("geometry masks: empty, invalid and malformed depth") {
  const RayCastScene s = ray_cast_scene();
  const GeometryMaskOptions o = scene_options();
  // All invalid: nothing to segment, no masks.
  CHECK(geometry_masks(cv::Mat1f(240, 320, 0.f), s.camera, o).empty());
  CHECK_THROWS_WITH(geometry_masks(cv::Mat(), s.camera, o, "view 'a'"),
                    Catch::Contains("view 'a'") && Catch::Contains("empty"));
  CHECK_THROWS_WITH(geometry_masks(cv::Mat1w(240, 320, ushort(1000)), s.camera, o),
                    Catch::Contains("not CV_32FC1 metres"));
  CHECK_THROWS_WITH(geometry_masks(cv::Mat1f(60, 80, 1.f), s.camera, o),
                    Catch::Contains("80x60") && Catch::Contains("320x240"));

  // A capture: a view without depth is named; one whose depth is all invalid gives no mask, and
  // a capture where no view gives one is an error, not an empty result.
  Capture capture;
  capture.name = "scene";
  View view;
  view.name = "v0";
  view.camera = s.camera;
  capture.views.push_back(view);
  GeometryMaskOptions all = o;
  all.keep.views = ViewSet::All;
  CHECK_THROWS_WITH(geometry_mask_set(capture, all),
                    Catch::Contains("'v0'") && Catch::Contains("no depth prior"));
  capture.views[0].depth = ImageSource::in_memory(cv::Mat1f(240, 320, 0.f));
  CHECK_THROWS_WITH(geometry_mask_set(capture, all), Catch::Contains("no view of 'scene'"));
  view.name = "v1";
  view.depth = ImageSource::in_memory(s.depth);
  capture.views.push_back(view);
  const MaskSet set = geometry_mask_set(capture, all);
  REQUIRE(set.views.size() == 2);
  CHECK(set.views[0].masks.empty());
  CHECK(set.views[1].masks.size() >= 6);  // floor, box, sphere at two granularities at least
}

TEST_CASE("geometry masks on a real RGB-D capture (Replica room0)") {
  GSLIFT_REQUIRE_SHARED_DATA("replica_nice_slam_rgbd");
  CaptureOptions load;
  load.downscale = 4;
  const Capture c = load_capture(test::shared_data("replica_nice_slam_rgbd/room0"), load);
  GeometryMaskOptions o;
  o.keep.views = ViewSet::All;
  o.normal_step = 2;
  o.keep.min_area = 30;
  const MaskSet set = geometry_mask_set(c, o);
  REQUIRE(set.views.size() == c.views.size());
  // Every frame of the room shows floor or walls and furniture: groups, objects and parts in
  // each (a finer granularity may have fewer masks: its pieces can fall under min_area).
  for (const ViewMasks& vm : set.views) {
    INFO(vm.view);
    int per[3] = {0, 0, 0};
    for (const Mask& m : vm.masks) ++per[m.granularity];
    CHECK(per[0] >= 3);
    CHECK(per[1] >= 3);
    CHECK(per[2] >= 3);
  }
  // The first frame's floor and walls are dominant planes.
  const View& first = c.views[0];
  CHECK(geometry_segments(first.depth.load(), first.camera, o).plane_count >= 2);
}
