// The small ideal pinholes the tests build their scenes with.
#pragma once

#include "nodes/scene/camera.hpp"

namespace gslift::test {

// width x height pixels, focal length `focal` in x and y, principal point at the image centre.
inline Camera centred_pinhole(int width, int height, double focal) {
  Camera c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = focal;
  c.cx = width / 2.0;
  c.cy = height / 2.0;
  return c;
}

}  // namespace gslift::test
