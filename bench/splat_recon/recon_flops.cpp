#include "recon_flops.hpp"

#include <immintrin.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/render_cache.hpp"

namespace gslift::bench {

StepFlops estimate_step_flops(const GaussianModel& model, const View& view) {
  RenderSettings settings;
  settings.depth = settings.normal = true;
  const RenderOutput out = render(model, view.camera, view.pose, settings);
  const RenderCache cache(out);
  const double pairs = static_cast<double>(cache.entries());
  const double pixels = static_cast<double>(out.width) * out.height;
  const double params =
      static_cast<double>(model.means.size() + model.log_scales.size() + model.quats.size() +
                          model.opacity_logits.size() + model.sh.size());
  StepFlops f;
  f.blend_forward = 40 * pairs;
  f.blend_backward = 90 * pairs;
  f.projection = 500 * static_cast<double>(model.size());
  // 5 windowed means forward + 3 adjoint filters, each 2 passes x 11 taps x (mul + add), on 3
  // channels, plus ~40 flops of per-pixel SSIM algebra and its derivative.
  f.ssim = (8 * 2 * 11 * 2 + 40) * 3 * pixels;
  f.adam = 12 * params;
  return f;
}

namespace {

constexpr int kChains = 12;  // > FMA latency (4 cycles) x pipes (2): the pipes never wait
constexpr long kRounds = 20'000'000;

// One thread's FMAs: kChains independent accumulators, each a = a * m + c per round. Returns the
// sum of their lanes so that the compiler keeps the work.
float fma_chains(float seed, int* lanes) {
#if defined(__AVX512F__)
  *lanes = 16;
  __m512 acc[kChains];
  for (int k = 0; k < kChains; ++k) acc[k] = _mm512_set1_ps(seed + k);
  const __m512 m = _mm512_set1_ps(0.999999f), c = _mm512_set1_ps(1e-7f);
  for (long r = 0; r < kRounds; ++r)
    for (int k = 0; k < kChains; ++k) acc[k] = _mm512_fmadd_ps(acc[k], m, c);
  float sum = 0;
  for (int k = 0; k < kChains; ++k) sum += _mm512_reduce_add_ps(acc[k]);
  return sum;
#elif defined(__AVX2__) && defined(__FMA__)
  *lanes = 8;
  __m256 acc[kChains];
  for (int k = 0; k < kChains; ++k) acc[k] = _mm256_set1_ps(seed + k);
  const __m256 m = _mm256_set1_ps(0.999999f), c = _mm256_set1_ps(1e-7f);
  for (long r = 0; r < kRounds; ++r)
    for (int k = 0; k < kChains; ++k) acc[k] = _mm256_fmadd_ps(acc[k], m, c);
  alignas(32) float out[8];
  float sum = 0;
  for (int k = 0; k < kChains; ++k) {
    _mm256_store_ps(out, acc[k]);
    for (float v : out) sum += v;
  }
  return sum;
#else
  *lanes = 1;
  float acc[kChains];
  for (int k = 0; k < kChains; ++k) acc[k] = seed + k;
  for (long r = 0; r < kRounds; ++r)
    for (int k = 0; k < kChains; ++k) acc[k] = acc[k] * 0.999999f + 1e-7f;
  float sum = 0;
  for (float v : acc) sum += v;
  return sum;
#endif
}

}  // namespace

FmaPeak measure_fma_peak(int threads) {
  FmaPeak peak;
  peak.threads = threads > 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
  double best = 0;
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<float> sums(peak.threads);
    std::vector<int> lanes(peak.threads, 1);
    std::vector<std::thread> workers;
    const auto t0 = std::chrono::steady_clock::now();
    for (int t = 0; t < peak.threads; ++t)
      workers.emplace_back([&, t] { sums[t] = fma_chains(float(t + trial), &lanes[t]); });
    for (std::thread& w : workers) w.join();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    peak.lanes = lanes[0];
    const double flops = 2.0 * peak.lanes * kChains * double(kRounds) * peak.threads;
    if (sums[0] != 0) best = std::max(best, flops / seconds * 1e-9);  // sums[0] keeps the loop
  }
  peak.gflops = best;
  return peak;
}

}  // namespace gslift::bench
