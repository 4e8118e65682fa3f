// Adam (Kingma & Ba 2015) over row-structured parameter arrays, with the bookkeeping density
// control needs: rows are Gaussians, and when Gaussians are cloned, split or pruned the moments
// follow their rows (3DGS's cat_tensors_to_optimizer / _prune_optimizer).
#pragma once

#include <cstddef>
#include <vector>

namespace gslift {

struct AdamSettings {
  double beta1 = 0.9;
  double beta2 = 0.999;
  double eps = 1e-15;  // 3DGS uses 1e-15: gradients of far Gaussians are tiny but meaningful
};

class AdamGroup {
 public:
  // width: floats per row (3 for means, 4 for quaternions, (sh_degree+1)^2 * 3 for SH, ...).
  explicit AdamGroup(int width, AdamSettings settings = {});

  // One Adam update of rows x width params in place:
  //   m = b1 m + (1-b1) g;  v = b2 v + (1-b2) g^2;  p -= lr_c * (m / (1-b1^t)) / (sqrt(v /
  //   (1-b2^t)) + eps)
  // with t the number of steps taken by this group (shared by all rows, as torch keeps one step
  // count per tensor) and lr_c = column_lr[c] for column c of a row. Grows the moments with zeros
  // when rows exceed the rows seen so far.
  void step(float* params, const float* grads, size_t rows, const float* column_lr);
  void step(float* params, const float* grads, size_t rows, float lr);

  // Re-indexes rows after density control: new row i takes the moments of old row source[i], or
  // zero moments when source[i] < 0 (a new Gaussian).
  void remap(const std::vector<int>& source);

  int steps_taken() const { return steps_; }
  const std::vector<float>& first_moment() const { return m_; }
  const std::vector<float>& second_moment() const { return v_; }

 private:
  int width_;
  AdamSettings settings_;
  int steps_ = 0;
  std::vector<float> m_, v_;
  std::vector<float> lr_pattern_;  // step's column rates repeated over a task's rows
};

// 3DGS's get_expon_lr_func without delay: the rate interpolates log-linearly from lr_init at
// step 0 to lr_final at max_steps (and stays there after).
double exponential_lr(double lr_init, double lr_final, int step, int max_steps);

}  // namespace gslift
