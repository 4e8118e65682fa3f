#include "nodes/synth/primitive.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gslift::synth {

namespace {

using Vec3 = Eigen::Vector3f;

// Smallest root of a t^2 + b t + c = 0 inside (t_min, t_max), or +inf.
float nearest_root(float a, float b, float c, float t_min, float t_max) {
  const float inf = std::numeric_limits<float>::infinity();
  if (a <= 0) return inf;
  const float disc = b * b - 4 * a * c;
  if (disc < 0) return inf;
  const float s = std::sqrt(disc);
  // Numerically stable pair of roots (avoids cancellation when b^2 >> 4ac).
  const float q = -0.5f * (b + std::copysign(s, b));
  float r0 = q / a, r1 = q != 0 ? c / q : r0;
  if (r0 > r1) std::swap(r0, r1);
  if (r0 > t_min && r0 < t_max) return r0;
  if (r1 > t_min && r1 < t_max) return r1;
  return inf;
}

// Local-frame intersections: o, d in the primitive frame; n is the local outward normal.
float hit_box(const Vec3& h, const Vec3& o, const Vec3& d, float t_min, float t_max, Vec3& n) {
  float t_near = -std::numeric_limits<float>::infinity();
  float t_far = std::numeric_limits<float>::infinity();
  int near_axis = 0, far_axis = 0;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12f) {
      if (std::abs(o[k]) > h[k]) return std::numeric_limits<float>::infinity();
      continue;
    }
    float t0 = (-h[k] - o[k]) / d[k], t1 = (h[k] - o[k]) / d[k];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_near) t_near = t0, near_axis = k;
    if (t1 < t_far) t_far = t1, far_axis = k;
  }
  if (t_near > t_far) return std::numeric_limits<float>::infinity();
  float t = t_near;
  int axis = near_axis;
  if (t <= t_min) t = t_far, axis = far_axis;  // origin inside the box: the exit face
  if (t <= t_min || t >= t_max) return std::numeric_limits<float>::infinity();
  const Vec3 p = o + t * d;
  n = Vec3::Zero();
  n[axis] = p[axis] > 0 ? 1.f : -1.f;
  return t;
}

float hit_ellipsoid(const Vec3& r, const Vec3& o, const Vec3& d, float t_min, float t_max,
                    Vec3& n) {
  // Scale the frame so that the ellipsoid is the unit sphere; t is unchanged by the scaling.
  const Vec3 os = o.cwiseQuotient(r), ds = d.cwiseQuotient(r);
  const float t = nearest_root(ds.dot(ds), 2 * os.dot(ds), os.dot(os) - 1, t_min, t_max);
  if (std::isfinite(t)) n = (o + t * d).cwiseQuotient(r.cwiseProduct(r)).normalized();
  return t;
}

// Infinite cylinder x^2 + y^2 = radius^2 around local z, limited to |z| <= half_z.
float hit_tube(float radius, float half_z, const Vec3& o, const Vec3& d, float t_min, float t_max,
               Vec3& n) {
  const float a = d.x() * d.x() + d.y() * d.y();
  const float b = 2 * (o.x() * d.x() + o.y() * d.y());
  const float c = o.x() * o.x() + o.y() * o.y() - radius * radius;
  const float inf = std::numeric_limits<float>::infinity();
  if (a <= 0) return inf;
  const float disc = b * b - 4 * a * c;
  if (disc < 0) return inf;
  const float s = std::sqrt(disc);
  for (float t : {(-b - s) / (2 * a), (-b + s) / (2 * a)}) {
    if (t <= t_min || t >= t_max) continue;
    const Vec3 p = o + t * d;
    if (std::abs(p.z()) > half_z) continue;
    n = Vec3(p.x(), p.y(), 0).normalized();
    return t;
  }
  return inf;
}

float hit_cylinder(const Vec3& h, const Vec3& o, const Vec3& d, float t_min, float t_max, Vec3& n) {
  // `best` doubles as the upper limit of the remaining tests, so it starts at t_max.
  float best = std::min(t_max, hit_tube(h.x(), h.z(), o, d, t_min, t_max, n));
  if (std::abs(d.z()) > 1e-12f) {
    for (float zc : {-h.z(), h.z()}) {
      const float t = (zc - o.z()) / d.z();
      if (t <= t_min || t >= best) continue;
      const Vec3 p = o + t * d;
      if (p.x() * p.x() + p.y() * p.y() > h.x() * h.x()) continue;
      best = t;
      n = Vec3(0, 0, zc > 0 ? 1.f : -1.f);
    }
  }
  return best < t_max ? best : std::numeric_limits<float>::infinity();
}

float hit_capsule(const Vec3& h, const Vec3& o, const Vec3& d, float t_min, float t_max, Vec3& n) {
  float best = std::min(t_max, hit_tube(h.x(), h.z(), o, d, t_min, t_max, n));
  const Vec3 r = Vec3::Constant(h.x());
  for (float zc : {-h.z(), h.z()}) {
    const Vec3 shift(0, 0, zc);
    Vec3 cap_n;
    const float t = hit_ellipsoid(r, o - shift, d, t_min, best, cap_n);
    if (t < best) best = t, n = cap_n;
  }
  return best < t_max ? best : std::numeric_limits<float>::infinity();
}

}  // namespace

bool intersect(const Primitive& p, const Vec3& origin, const Vec3& dir, float t_min, float t_max,
               Hit& hit) {
  const Vec3 o = p.rotation.transpose() * (origin - p.centre);
  const Vec3 d = p.rotation.transpose() * dir;
  Vec3 n;
  float t = std::numeric_limits<float>::infinity();
  switch (p.shape) {
    case Shape::Box:
      t = hit_box(p.half_extents, o, d, t_min, t_max, n);
      break;
    case Shape::Sphere:
      t = hit_ellipsoid(Vec3::Constant(p.half_extents.x()), o, d, t_min, t_max, n);
      break;
    case Shape::Ellipsoid:
      t = hit_ellipsoid(p.half_extents, o, d, t_min, t_max, n);
      break;
    case Shape::Cylinder:
      t = hit_cylinder(p.half_extents, o, d, t_min, t_max, n);
      break;
    case Shape::Capsule:
      t = hit_capsule(p.half_extents, o, d, t_min, t_max, n);
      break;
  }
  if (!std::isfinite(t)) return false;
  hit.t = t;
  hit.normal = p.rotation * n;
  return true;
}

Eigen::AlignedBox3f bounds(const Primitive& p) {
  Vec3 local = p.half_extents;  // Box, Ellipsoid
  switch (p.shape) {
    case Shape::Box:
    case Shape::Ellipsoid:
      break;
    case Shape::Sphere:
      local = Vec3::Constant(p.half_extents.x());
      break;
    case Shape::Cylinder:
      local = Vec3(p.half_extents.x(), p.half_extents.x(), p.half_extents.z());
      break;
    case Shape::Capsule:
      local = Vec3(p.half_extents.x(), p.half_extents.x(), p.half_extents.z() + p.half_extents.x());
      break;
  }
  // Extent of a rotated box along world axis i: sum_j |R_ij| h_j.
  const Vec3 extent = p.rotation.cwiseAbs() * local;
  return Eigen::AlignedBox3f(p.centre - extent, p.centre + extent);
}

}  // namespace gslift::synth
