// One view's rendered feature image F(p) (LangOR Eq. 1): what lifting clusters and association
// matches the lifted instances against.
#pragma once

#include <cstddef>
#include <vector>

#include "base/uninit_vector.hpp"

namespace gslift {

// Row-major, `dim` floats per pixel.
struct FeatureMap {
  int width = 0;
  int height = 0;
  int dim = 0;
  // height * width * dim; not zeroed on resize: a rendered map writes every pixel, and a zero
  // fill of 4 views x 32 channels was a serial pass with its page faults.
  UninitVector<float> values;

  const float* at(int x, int y) const {
    return values.data() + (static_cast<size_t>(y) * width + x) * dim;
  }
};

}  // namespace gslift
