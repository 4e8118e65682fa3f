#include "nodes/splat/adam.hpp"

#include <algorithm>
#include <cmath>

namespace gslift {

AdamGroup::AdamGroup(int width, AdamSettings settings) : width_(width), settings_(settings) {}

void AdamGroup::step(float* params, const float* grads, size_t rows, const float* column_lr) {
  const size_t n = rows * static_cast<size_t>(width_);
  if (m_.size() < n) {
    m_.resize(n, 0.f);
    v_.resize(n, 0.f);
  }
  ++steps_;
  const double b1 = settings_.beta1, b2 = settings_.beta2;
  const double bias1 = 1 - std::pow(b1, steps_);
  const double bias2 = 1 - std::pow(b2, steps_);
  for (size_t i = 0; i < n; ++i) {
    const double g = grads[i];
    const double m = b1 * m_[i] + (1 - b1) * g;
    const double v = b2 * v_[i] + (1 - b2) * g * g;
    m_[i] = static_cast<float>(m);
    v_[i] = static_cast<float>(v);
    const double lr = column_lr[i % width_];
    params[i] -= static_cast<float>(lr * (m / bias1) / (std::sqrt(v / bias2) + settings_.eps));
  }
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
