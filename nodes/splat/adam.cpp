#include "nodes/splat/adam.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

namespace gslift {

namespace {

// One step's constants (AdamGroup::step).
struct AdamConstants {
  float b1, a1, b2, a2, inv_bias1, inv_sqrt_bias2, eps;
};

// The update of `count` consecutive elements, element i at rate lr[i]. Distinct arrays, said
// with __restrict, and square roots without errno (CMakeLists.txt): GCC vectorises the loop,
// which as the body of the parallel loop, over captured pointers, stayed scalar (Adam 4% of the
// main job's samples, 1.2% vectorised).
void update(const AdamConstants& k, float* __restrict params, const float* __restrict grads,
            float* __restrict m, float* __restrict v, const float* __restrict lr, size_t count) {
  for (size_t i = 0; i < count; ++i) {
    const float g = grads[i];
    m[i] = k.b1 * m[i] + k.a1 * g;
    v[i] = k.b2 * v[i] + k.a2 * g * g;
    params[i] -= lr[i] * k.inv_bias1 * m[i] / (std::sqrt(v[i]) * k.inv_sqrt_bias2 + k.eps);
  }
}

}  // namespace

AdamGroup::AdamGroup(int width, AdamSettings settings) : width_(width), settings_(settings) {}

void AdamGroup::step(float* params, const float* grads, size_t rows, const float* column_lr) {
  const size_t n = rows * static_cast<size_t>(width_);
  if (m_.size() < n) {
    m_.resize(n, 0.f);
    v_.resize(n, 0.f);
  }
  ++steps_;
  AdamConstants k;
  k.b1 = static_cast<float>(settings_.beta1);
  k.b2 = static_cast<float>(settings_.beta2);
  // 1 - beta in double first: 1 - 0.999f in float is off by 1e-5 relative.
  k.a1 = static_cast<float>(1 - settings_.beta1);
  k.a2 = static_cast<float>(1 - settings_.beta2);
  k.eps = static_cast<float>(settings_.eps);
  // lr * (m / bias1) / (sqrt(v / bias2) + eps) = (lr / bias1) m / (sqrt(v) / sqrt(bias2) + eps):
  // the bias corrections fold into two per-step constants. Float arithmetic (as torch's Adam on
  // float32 parameters), parallel over rows: each element's update is independent, so the result
  // does not depend on the thread count.
  k.inv_bias1 = static_cast<float>(1 / (1 - std::pow(settings_.beta1, steps_)));
  k.inv_sqrt_bias2 = static_cast<float>(1 / std::sqrt(1 - std::pow(settings_.beta2, steps_)));
  // One flat loop over the elements of a range of rows, with each element's rate from a pattern
  // of the column rates repeated over a task's rows: a loop over the few columns of a row (1 to
  // 48) is too short to vectorise.
  // simple_partitioner: ranges of at most this many rows. 4096 left the main job's 45k rows in
  // 11 tasks, and one thread ran the last alone at every step (perf samples matched in time).
  constexpr size_t kRowsPerTask = 1024;
  const size_t width = static_cast<size_t>(width_);
  // Rebuilt each step (the means' rate decays), in the group's buffer, by doubling copies of the
  // first row.
  std::vector<float>& lr_pattern = lr_pattern_;
  lr_pattern.resize(std::min(rows, kRowsPerTask) * width);
  if (!lr_pattern.empty()) std::copy_n(column_lr, width, lr_pattern.begin());
  for (size_t filled = width; filled < lr_pattern.size(); filled *= 2)
    std::copy_n(lr_pattern.begin(), std::min(filled, lr_pattern.size() - filled),
                lr_pattern.begin() + filled);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, rows, kRowsPerTask),
      [&](const tbb::blocked_range<size_t>& r) {
        const size_t begin = r.begin() * width;
        update(k, params + begin, grads + begin, m_.data() + begin, v_.data() + begin,
               lr_pattern.data(), r.size() * width);
      },
      tbb::simple_partitioner());
}

void AdamGroup::step(float* params, const float* grads, size_t rows, float lr) {
  const std::vector<float> column_lr(width_, lr);
  step(params, grads, rows, column_lr.data());
}

void AdamGroup::remap(const std::vector<int>& source) {
  std::vector<float> m(source.size() * width_, 0.f), v(source.size() * width_, 0.f);
  for (size_t i = 0; i < source.size(); ++i) {
    const size_t from = static_cast<size_t>(source[i]) * width_;
    if (source[i] < 0 || from + width_ > m_.size()) continue;
    std::copy_n(m_.begin() + from, width_, m.begin() + i * width_);
    std::copy_n(v_.begin() + from, width_, v.begin() + i * width_);
  }
  m_ = std::move(m);
  v_ = std::move(v);
}

double exponential_lr(double lr_init, double lr_final, int step, int max_steps) {
  if (max_steps <= 0) return lr_final;
  const double t = std::clamp(static_cast<double>(step) / max_steps, 0.0, 1.0);
  return std::exp(std::log(lr_init) * (1 - t) + std::log(lr_final) * t);
}

}  // namespace gslift
