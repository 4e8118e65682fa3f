// Real spherical harmonics up to degree 3 with the constants and sign conventions of the 3DGS
// reference code (eval_sh in utils/sh_utils.py and forward.cu), so SH coefficients read from an
// INRIA PLY give the same colours here.
#pragma once

#include <Eigen/Core>

namespace gslift {

constexpr int kMaxShCoeffs = 16;  // (3 + 1)^2

// Evaluates the (degree+1)^2 basis functions at the unit direction dir into basis[]. When
// gradient is given, gradient[k] receives d basis[k] / d dir (the polynomial's gradient; the
// caller projects it through the normalisation of dir).
void sh_basis(int degree, const Eigen::Vector3f& dir, float* basis,
              Eigen::Vector3f* gradient = nullptr);

}  // namespace gslift
