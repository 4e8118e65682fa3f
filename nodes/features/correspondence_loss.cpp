#include "nodes/features/correspondence_loss.hpp"

#include <stdexcept>

namespace gslift {

MaskedPixels masked_pixels(const ViewMasks& vm, size_t pixels) {
  MaskedPixels v;
  v.membership.words = static_cast<int>((vm.masks.size() + 63) / 64);
  v.membership.bits.assign(pixels * v.membership.words, 0);
  for (size_t m = 0; m < vm.masks.size(); ++m) {
    const cv::Mat1b px =
        vm.masks[m].pixels.isContinuous() ? vm.masks[m].pixels : vm.masks[m].pixels.clone();
    for (size_t p = 0; p < pixels; ++p)
      if (px.data[p]) v.membership.bits[p * v.membership.words + m / 64] |= uint64_t(1) << (m % 64);
  }
  for (size_t p = 0; p < pixels; ++p)
    for (int w = 0; w < v.membership.words; ++w)
      if (v.membership.pixel(p)[w]) {
        v.covered.push_back(static_cast<uint32_t>(p));
        break;
      }
  return v;
}

float mask_set_affinity(const uint64_t* a, const uint64_t* b, int words) {
  int both = 0, either = 0;
  for (int w = 0; w < words; ++w) {
    both += __builtin_popcountll(a[w] & b[w]);
    either += __builtin_popcountll(a[w] | b[w]);
  }
  return both == 0 ? -1.f : static_cast<float>(both) / static_cast<float>(either);
}

Eigen::MatrixXf correspondence_kernel(const MaskMembership& m,
                                      const std::vector<uint32_t>& pixels) {
  const int n = static_cast<int>(pixels.size());
  Eigen::MatrixXf k = Eigen::MatrixXf::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      k(i, j) = k(j, i) = mask_set_affinity(m.pixel(pixels[i]), m.pixel(pixels[j]), m.words);
  return k;
}

double correspondence_loss(const Eigen::MatrixXf& f, const Eigen::MatrixXf& kernel,
                           Eigen::MatrixXf* grad) {
  const Eigen::Index n = f.rows();
  if (n < 2 || kernel.rows() != n || kernel.cols() != n)
    throw std::invalid_argument("correspondence_loss: needs >= 2 pixels and a P x P kernel");
  const Eigen::VectorXf norm = f.rowwise().norm();
  Eigen::MatrixXf u = f;
  for (Eigen::Index i = 0; i < n; ++i)
    u.row(i) =
        norm(i) > 1e-12f ? (f.row(i) / norm(i)).eval() : Eigen::RowVectorXf::Zero(f.cols()).eval();
  Eigen::MatrixXf k = kernel;
  k.diagonal().setZero();
  const double pairs = 0.5 * double(n) * double(n - 1);
  // g = K U; sum_{i<j} K_ij cos_ij = 0.5 sum_i <g_i, u_i>.
  const Eigen::MatrixXf g = k * u;
  const double loss = -0.5 * double((g.array() * u.array()).sum()) / pairs;
  if (grad) {
    grad->resize(n, f.cols());
    for (Eigen::Index i = 0; i < n; ++i) {
      if (norm(i) <= 1e-12f) {
        grad->row(i).setZero();
        continue;
      }
      const float along = g.row(i).dot(u.row(i));
      grad->row(i) = -(g.row(i) - along * u.row(i)) / static_cast<float>(norm(i) * pairs);
    }
  }
  return loss;
}

}  // namespace gslift
