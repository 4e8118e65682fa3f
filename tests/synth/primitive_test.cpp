// Ray-primitive intersections against hand-computed distances, and the BVH against brute force.
#include <cmath>
#include <limits>

#include "base/random.hpp"
#include "nodes/synth/bvh.hpp"
#include "nodes/synth/primitive.hpp"
#include "tests/test_support.hpp"

using namespace gslift::synth;
using gslift::RandomStream;
using Vec3 = Eigen::Vector3f;

namespace {

Primitive make(Shape s, const Vec3& c, const Vec3& h,
               const Eigen::Matrix3f& r = Eigen::Matrix3f::Identity()) {
  Primitive p;
  p.shape = s;
  p.centre = c;
  p.half_extents = h;
  p.rotation = r;
  return p;
}

}  // namespace

TEST_CASE("ray hits each shape at the hand-computed distance with an outward unit normal") {
  Hit hit;
  const Vec3 o(0, 0, 0), x = Vec3::UnitX();
  SECTION("sphere radius 1 at x = 5: t = 4, normal -x") {
    REQUIRE(intersect(make(Shape::Sphere, Vec3(5, 0, 0), Vec3(1, 1, 1)), o, x, 0, 100, hit));
    CHECK(hit.t == Approx(4.f));
    CHECK(hit.normal.x() == Approx(-1.f));
  }
  SECTION("ellipsoid semi-axis 2 along x at x = 5: t = 3") {
    REQUIRE(intersect(make(Shape::Ellipsoid, Vec3(5, 0, 0), Vec3(2, 1, 1)), o, x, 0, 100, hit));
    CHECK(hit.t == Approx(3.f));
  }
  SECTION("box rotated 45 degrees about z: the ray meets the edge at 5 - sqrt(2)") {
    const Eigen::Matrix3f r = Eigen::AngleAxisf(M_PI / 4, Vec3::UnitZ()).toRotationMatrix();
    REQUIRE(intersect(make(Shape::Box, Vec3(5, 0.01f, 0), Vec3(1, 1, 1), r), o, x, 0, 100, hit));
    CHECK(hit.t == Approx(5 - std::sqrt(2.f)).margin(0.02));
    CHECK(hit.normal.norm() == Approx(1.f));
  }
  SECTION("cylinder along z seen from the side (t = 4.5) and from above its cap (t = 2)") {
    const Primitive cyl = make(Shape::Cylinder, Vec3(5, 0, 0), Vec3(0.5f, 0.5f, 1));
    REQUIRE(intersect(cyl, o, x, 0, 100, hit));
    CHECK(hit.t == Approx(4.5f));
    REQUIRE(intersect(cyl, Vec3(5, 0.2f, 3), -Vec3::UnitZ(), 0, 100, hit));
    CHECK(hit.t == Approx(2.f));
    CHECK(hit.normal.z() == Approx(1.f));
  }
  SECTION("capsule along z: side t = 4.5; the top cap sphere at z = 1 + 0.5 from above") {
    const Primitive cap = make(Shape::Capsule, Vec3(5, 0, 0), Vec3(0.5f, 0.5f, 1));
    REQUIRE(intersect(cap, o, x, 0, 100, hit));
    CHECK(hit.t == Approx(4.5f));
    REQUIRE(intersect(cap, Vec3(5, 0, 4), -Vec3::UnitZ(), 0, 100, hit));
    CHECK(hit.t == Approx(2.5f));
  }
  SECTION("misses and t_max limits") {
    CHECK_FALSE(intersect(make(Shape::Sphere, Vec3(5, 3, 0), Vec3(1, 1, 1)), o, x, 0, 100, hit));
    CHECK_FALSE(intersect(make(Shape::Sphere, Vec3(5, 0, 0), Vec3(1, 1, 1)), o, x, 0, 3.9f, hit));
  }
}

TEST_CASE("BVH closest hit equals brute force over random rays") {
  RandomStream rng(42);
  std::vector<Primitive> prims;
  const Shape shapes[] = {Shape::Box, Shape::Sphere, Shape::Ellipsoid, Shape::Cylinder,
                          Shape::Capsule};
  for (int i = 0; i < 120; ++i) {
    const Eigen::Matrix3f r =
        Eigen::AngleAxisf(static_cast<float>(rng.uniform(0, 3)),
                          Vec3(rng.normal(), rng.normal(), rng.normal()).normalized().cast<float>())
            .toRotationMatrix();
    prims.push_back(make(
        shapes[i % 5],
        Vec3(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5)).cast<float>(),
        Vec3(rng.uniform(0.1, 0.6), rng.uniform(0.1, 0.6), rng.uniform(0.1, 0.6)).cast<float>(),
        r));
  }
  const Bvh bvh(prims);
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 o = Vec3(rng.uniform(-8, 8), rng.uniform(-8, 8), rng.uniform(-8, 8)).cast<float>();
    const Vec3 d = Vec3(rng.normal(), rng.normal(), rng.normal()).cast<float>().normalized();
    float best = std::numeric_limits<float>::infinity();
    for (const Primitive& p : prims) {
      Hit h;
      if (intersect(p, o, d, 1e-4f, 100, h)) best = std::min(best, h.t);
    }
    const RayHit rh = bvh.closest(o, d, 1e-4f, 100);
    REQUIRE((rh.primitive >= 0) == std::isfinite(best));
    if (rh.primitive < 0) continue;
    ++hits;
    CHECK(rh.hit.t == Approx(best));
    CHECK(bvh.occluded(o, d, 1e-4f, best + 1e-3f));
    CHECK_FALSE(bvh.occluded(o, d, 1e-4f, best * 0.999f));
  }
  CHECK(hits > 200);  // the test exercised real hits
}
