// Analytic shapes the embedded operating room is built from, and their exact ray intersections.
// Every shape is defined in its own local frame (centre + rotation); a ray is moved into that
// frame, intersected there and the normal rotated back, so each shape is a few lines of algebra.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace gslift::synth {

enum class Shape {
  Box,        // half_extents = half side lengths along the local axes
  Sphere,     // half_extents.x() = radius
  Ellipsoid,  // half_extents = semi-axes
  Cylinder,   // half_extents.x() = radius, half_extents.z() = half height along local z; capped
  Capsule,    // half_extents.x() = radius, half_extents.z() = half length of the core segment
};

// Surface appearance, evaluated at the hit point by the renderer.
enum class Texture {
  Flat,     // uniform colour: drapes are deliberately textureless
  Fabric,   // value noise at cloth scale (gowns, caps)
  Tiles,    // floor tiles with dark grout lines
  Speckle,  // fine noise (painted metal, walls)
};

struct Material {
  Eigen::Vector3f albedo{0.7f, 0.7f, 0.7f};  // linear RGB in [0, 1]
  Texture texture = Texture::Flat;
};

struct Primitive {
  Shape shape = Shape::Box;
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  Eigen::Matrix3f rotation = Eigen::Matrix3f::Identity();  // local -> world
  Eigen::Vector3f half_extents{0.5f, 0.5f, 0.5f};
  Material material;
  int instance = 0;  // instance id, 0 = room (background)
  int semantic = 0;  // class id, 0 = background
  int part = 0;      // part of the instance (head, torso, ...), used by the SAM part simulation
  // False for the room's shell: lights are inside the (convex) room, so floor, walls and ceiling
  // can never block them, and shadow rays skip the shell.
  bool casts_shadow = true;
};

struct Hit {
  float t = 0;             // distance along the (unit) ray direction
  Eigen::Vector3f normal;  // world-space unit outward normal
};

// Nearest intersection with t in (t_min, t_max); false when there is none. `dir` must be unit.
bool intersect(const Primitive& p, const Eigen::Vector3f& origin, const Eigen::Vector3f& dir,
               float t_min, float t_max, Hit& hit);

// World-space axis-aligned bounds, for the BVH.
Eigen::AlignedBox3f bounds(const Primitive& p);

}  // namespace gslift::synth
