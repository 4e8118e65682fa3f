#include "nodes/splat/sh.hpp"

namespace gslift {

namespace {
constexpr float kC0 = 0.28209479177387814f;
constexpr float kC1 = 0.4886025119029199f;
constexpr float kC2[5] = {1.0925484305920792f, -1.0925484305920792f, 0.31539156525252005f,
                          -1.0925484305920792f, 0.5462742152960396f};
constexpr float kC3[7] = {-0.5900435899266435f, 2.890611442640554f,   -0.4570457994644658f,
                          0.3731763325901154f,  -0.4570457994644658f, 1.445305721320277f,
                          -0.5900435899266435f};
}  // namespace

void sh_basis(int degree, const Eigen::Vector3f& dir, float* basis, Eigen::Vector3f* gradient) {
  const float x = dir.x(), y = dir.y(), z = dir.z();
  basis[0] = kC0;
  if (gradient) gradient[0].setZero();
  if (degree < 1) return;
  basis[1] = -kC1 * y;
  basis[2] = kC1 * z;
  basis[3] = -kC1 * x;
  if (gradient) {
    gradient[1] = {0.f, -kC1, 0.f};
    gradient[2] = {0.f, 0.f, kC1};
    gradient[3] = {-kC1, 0.f, 0.f};
  }
  if (degree < 2) return;
  const float xx = x * x, yy = y * y, zz = z * z, xy = x * y, yz = y * z, xz = x * z;
  basis[4] = kC2[0] * xy;
  basis[5] = kC2[1] * yz;
  basis[6] = kC2[2] * (2.f * zz - xx - yy);
  basis[7] = kC2[3] * xz;
  basis[8] = kC2[4] * (xx - yy);
  if (gradient) {
    gradient[4] = kC2[0] * Eigen::Vector3f(y, x, 0.f);
    gradient[5] = kC2[1] * Eigen::Vector3f(0.f, z, y);
    gradient[6] = kC2[2] * Eigen::Vector3f(-2.f * x, -2.f * y, 4.f * z);
    gradient[7] = kC2[3] * Eigen::Vector3f(z, 0.f, x);
    gradient[8] = kC2[4] * Eigen::Vector3f(2.f * x, -2.f * y, 0.f);
  }
  if (degree < 3) return;
  basis[9] = kC3[0] * y * (3.f * xx - yy);
  basis[10] = kC3[1] * xy * z;
  basis[11] = kC3[2] * y * (4.f * zz - xx - yy);
  basis[12] = kC3[3] * z * (2.f * zz - 3.f * xx - 3.f * yy);
  basis[13] = kC3[4] * x * (4.f * zz - xx - yy);
  basis[14] = kC3[5] * z * (xx - yy);
  basis[15] = kC3[6] * x * (xx - 3.f * yy);
  if (gradient) {
    gradient[9] = kC3[0] * Eigen::Vector3f(6.f * xy, 3.f * xx - 3.f * yy, 0.f);
    gradient[10] = kC3[1] * Eigen::Vector3f(yz, xz, xy);
    gradient[11] = kC3[2] * Eigen::Vector3f(-2.f * xy, 4.f * zz - xx - 3.f * yy, 8.f * yz);
    gradient[12] = kC3[3] * Eigen::Vector3f(-6.f * xz, -6.f * yz, 6.f * zz - 3.f * xx - 3.f * yy);
    gradient[13] = kC3[4] * Eigen::Vector3f(4.f * zz - 3.f * xx - yy, -2.f * xy, 8.f * xz);
    gradient[14] = kC3[5] * Eigen::Vector3f(2.f * xz, -2.f * yz, xx - yy);
    gradient[15] = kC3[6] * Eigen::Vector3f(3.f * xx - 3.f * yy, -6.f * xy, 0.f);
  }
}

}  // namespace gslift
