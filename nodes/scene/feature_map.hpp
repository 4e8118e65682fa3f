// One view's rendered feature image F(p) (LangOR Eq. 1): what lifting clusters and association
// matches the lifted instances against.
#pragma once

#include <cstddef>
#include <vector>

namespace gslift {

// Row-major, `dim` floats per pixel.
struct FeatureMap {
  int width = 0;
  int height = 0;
  int dim = 0;
  std::vector<float> values;  // height * width * dim

  const float* at(int x, int y) const {
    return values.data() + (static_cast<size_t>(y) * width + x) * dim;
  }
};

}  // namespace gslift
