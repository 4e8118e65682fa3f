#include "nodes/splat/ssim.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace gslift {
namespace {

constexpr double kC1 = 0.01 * 0.01;
constexpr double kC2 = 0.03 * 0.03;
constexpr int kRadius = 5;  // 11 taps
constexpr int kTaps = 2 * kRadius + 1;

// Normalised 1D Gaussian, sigma 1.5 (3DGS's gaussian(11, 1.5)); the 2D window is its outer product.
std::array<float, kTaps> window_taps() {
  std::array<double, kTaps> w{};
  double sum = 0;
  for (int k = 0; k < kTaps; ++k) {
    const double d = k - kRadius;
    w[k] = std::exp(-d * d / (2 * 1.5 * 1.5));
    sum += w[k];
  }
  std::array<float, kTaps> out{};
  for (int k = 0; k < kTaps; ++k) out[k] = static_cast<float>(w[k] / sum);
  return out;
}

void require_ssim_inputs(const cv::Mat& x, const cv::Mat& y) {
  if (x.size() != y.size() || x.type() != y.type() || x.depth() != CV_32F)
    throw std::invalid_argument("ssim: images must be CV_32F of the same size and channels");
}

// The window's weights as a plain array (the vector loops below read them as constants).
const float* taps() {
  static const std::array<float, kTaps> w = window_taps();
  return w.data();
}

// The horizontal pass of one row: out[i] = sum_k w[k] col[i + (k - kRadius) channels], summed in
// tap order from zero, col having kRadius zero pixels either side (the zero padding). Tap-inner,
// so each sum stays in a register.
void horizontal_pass(const float* __restrict col, int width, int channels, float* __restrict out) {
  const float* w = taps();
  for (int i = 0; i < width; ++i) {
    float acc = 0.f;
    for (int k = 0; k < kTaps; ++k) acc += w[k] * col[i + (k - kRadius) * channels];
    out[i] = acc;
  }
}

// The vertical pass of one window row for N images: padded[n][i] = sum_k w[k] value(n, rows[k], i),
// summed in tap order from zero, where rows[k] holds the sources' row r + k - kRadius (a zero row
// past the image's edges: adding w x 0 to a sum that starts at +0, and so is never -0, leaves it
// unchanged, the same as skipping the tap). All taps of a vector of pixels are summed in
// registers and stored once; a multiply-add over the whole row per tap read and wrote the row
// buffer eleven times, and SSIM was store-bound (12% of a DTU step at 800x600).
template <int N, class RowSet, class Value>
void vertical_pass(const RowSet (&rows)[kTaps], int width, Value&& value, float* const padded[N]) {
  const float* w = taps();
#if defined(__GNUC__) && !defined(__clang__)  // the release build's compiler; clang lacks ivdep
#pragma GCC ivdep  // padded never aliases the source rows (too many pointers to check at run time)
#endif
  for (int i = 0; i < width; ++i) {
    float acc[N] = {};
#pragma GCC unroll 11
    for (int k = 0; k < kTaps; ++k)
#pragma GCC unroll 3
      for (int n = 0; n < N; ++n) acc[n] += w[k] * value(n, rows[k], i);
#pragma GCC unroll 3
    for (int n = 0; n < N; ++n) padded[n][i] = acc[n];
  }
}

// Per-thread buffers of window_row for N images: the vertical pass's rows with kRadius zero
// pixels either side of each (the zero padding), N output rows, and a zero source row.
template <int N>
struct WindowRows {
  WindowRows(int cols, int channels)
      : width(cols * channels),
        stride((cols + 2 * kRadius) * channels),
        padded_buffer(N * stride, 0.f),
        out_buffer(N * width),
        zero(width, 0.f) {
    for (int n = 0; n < N; ++n) {
      padded[n] = padded_buffer.data() + n * stride + kRadius * channels;
      out[n] = out_buffer.data() + n * width;
    }
  }
  int width, stride;
  std::vector<float> padded_buffer, out_buffer, zero;
  float* padded[N];
  float* out[N];
};

// Window row r (of an image of `rows` rows) for N images at once: the vertical pass over
// source_rows(source), the M source images' rows at `source` (std::array<const float*, M>), each
// pixel's N values value(n, sources, i), then the horizontal pass into out[n]. Windowing the images
// a loss needs together keeps each row's sums in row buffers instead of image-sized temporaries
// (written once and read once per step, and freshly mapped memory at every step).
template <int N, class SourceRows, class Value>
void window_row(int r, int rows, int channels, SourceRows&& source_rows, Value&& value,
                WindowRows<N>& buffers) {
  using RowSet = decltype(source_rows(0));
  RowSet taps_rows[kTaps];
  for (int k = 0; k < kTaps; ++k) {
    const int source = r + k - kRadius;
    if (source >= 0 && source < rows) {
      taps_rows[k] = source_rows(source);
    } else {
      for (auto& row : taps_rows[k]) row = buffers.zero.data();
    }
  }
  vertical_pass<N>(taps_rows, buffers.width, value, buffers.padded);
  for (int n = 0; n < N; ++n)
    horizontal_pass(buffers.padded[n], buffers.width, channels, buffers.out[n]);
}

// One row's SSIM per value, s[i], and with kGrad the gradient of g x their sum with respect to
// the windowed moments of x: dmu, dxx, dxy. Float arithmetic (as the 3DGS reference in torch
// float32) in a loop over distinct arrays that vectorises: with the gradient as a branch inside
// it and the rows reached through the caller's pointers, it stayed scalar (half of SSIM's
// samples, perf annotate). The caller sums the row in double (a double sum inside kept it
// scalar too).
template <bool kGrad>
void ssim_values(const float* __restrict mx, const float* __restrict my, const float* __restrict xx,
                 const float* __restrict yy, const float* __restrict xy, int width, float c1,
                 float c2, float g, float* __restrict s_out, float* __restrict dmu,
                 float* __restrict dxx, float* __restrict dxy) {
  for (int i = 0; i < width; ++i) {
    // S = A B / (C D), A = 2 mx my + C1, B = 2 sxy + C2, C = mx^2 + my^2 + C1,
    // D = sxx + syy + C2.
    const float a_mx = mx[i], a_my = my[i];
    const float sxx = xx[i] - a_mx * a_mx, syy = yy[i] - a_my * a_my;
    const float sxy = xy[i] - a_mx * a_my;
    const float A = 2 * a_mx * a_my + c1, B = 2 * sxy + c2;
    const float C = a_mx * a_mx + a_my * a_my + c1, D = sxx + syy + c2;
    const float inv_cd = 1.f / (C * D);
    const float s = A * B * inv_cd;
    s_out[i] = s;
    if constexpr (kGrad) {
      const float ds_dsxx = -s / D;
      const float ds_dsxy = 2 * A * inv_cd;
      // mx enters A, C directly and sxx, sxy through -mx^2 and -mx my.
      const float ds_dmx =
          2 * a_my * B * inv_cd - s * 2 * a_mx / C + ds_dsxx * (-2 * a_mx) + ds_dsxy * (-a_my);
      dmu[i] = g * ds_dmx;
      dxx[i] = g * ds_dsxx;
      dxy[i] = g * ds_dsxy;
    }
  }
}

constexpr int kSumRows = 4;

// sums[k] = the sum in double of row k of K rows of `width` floats, added in index order from
// zero. A row's sum is one chain of dependent adds (a row alone was 12% of SSIM's samples, an
// add's latency per value); K rows side by side overlap their chains, each row still summed in
// the same order.
template <int K>
void sum_rows(const float* rows, int width, double* sums) {
  double acc[K] = {};
  for (int i = 0; i < width; ++i)
#pragma GCC unroll 4
    for (int k = 0; k < K; ++k) acc[k] += rows[size_t(k) * width + i];
  std::copy_n(acc, K, sums);
}

// The same for `count` (1 .. kSumRows) rows.
void sum_rows(const float* rows, int count, int width, double* sums) {
  static_assert(kSumRows == 4, "one case per row count");
  switch (count) {
    case 4:
      return sum_rows<4>(rows, width, sums);
    case 3:
      return sum_rows<3>(rows, width, sums);
    case 2:
      return sum_rows<2>(rows, width, sums);
    default:
      return sum_rows<1>(rows, width, sums);
  }
}

}  // namespace

cv::Mat ssim_window(const cv::Mat& image) {
  cv::Mat out(image.size(), image.type());
  const int channels = image.channels();
  tbb::parallel_for(tbb::blocked_range<int>(0, image.rows, 16), [&](const auto& range) {
    WindowRows<1> buffers(image.cols, channels);
    const auto source_rows = [&](int source) {
      return std::array<const float*, 1>{image.ptr<float>(source)};
    };
    const auto value = [](int, const std::array<const float*, 1>& p, int i) { return p[0][i]; };
    for (int r = range.begin(); r < range.end(); ++r) {
      window_row<1>(r, image.rows, channels, source_rows, value, buffers);
      std::copy_n(buffers.out[0], buffers.width, out.ptr<float>(r));
    }
  });
  return out;
}

SsimTarget::SsimTarget(const cv::Mat& target)
    : image(target), mean(ssim_window(target)), mean_sq(ssim_window(target.mul(target))) {}

double ssim(const cv::Mat& x, const SsimTarget& target, cv::Mat* grad_x) {
  const cv::Mat& y = target.image;
  require_ssim_inputs(x, y);
  const int channels = x.channels(), width = x.cols * channels;
  const size_t count = x.total() * channels;
  cv::Mat d_mu, d_exx, d_exy;  // dSSIM/d(windowed means), per pixel
  if (grad_x) {
    d_mu.create(x.size(), x.type());
    d_exx.create(x.size(), x.type());
    d_exy.create(x.size(), x.type());
  }
  const float g = static_cast<float>(1.0 / static_cast<double>(count));
  const float c1 = static_cast<float>(kC1), c2 = static_cast<float>(kC2);
  // Row sums are reduced in a fixed row order (deterministic at any thread count).
  std::vector<double> row_sum(x.rows, 0.0);
  // One set of row buffers per thread for the call, not per task: a set per task (30 a call)
  // had the allocator hand out freshly mapped pages at every step (the main job's page faults
  // doubled and SSIM ran slower than with the image temporaries).
  tbb::enumerable_thread_specific<WindowRows<3>> buffers(x.cols, channels);
  tbb::parallel_for(tbb::blocked_range<int>(0, x.rows, 16), [&](const tbb::blocked_range<int>& rr) {
    // Each row's windowed x, x^2 and x y (the products formed as the window reads them).
    WindowRows<3>& windowed = buffers.local();
    const auto source_rows = [&](int source) {
      return std::array<const float*, 2>{x.ptr<float>(source), y.ptr<float>(source)};
    };
    const auto value = [](int n, const std::array<const float*, 2>& p, int i) {
      const float xs = p[0][i];
      return n == 0 ? xs : n == 1 ? xs * xs : xs * p[1][i];
    };
    // The SSIM values of up to kSumRows rows, summed together once they are all in.
    std::vector<float> row_ssim(size_t(kSumRows) * width);
    for (int r = rr.begin(); r < rr.end(); ++r) {
      const int slot = (r - rr.begin()) % kSumRows;
      float* values = row_ssim.data() + size_t(slot) * width;
      window_row<3>(r, x.rows, channels, source_rows, value, windowed);
      const float* mx = windowed.out[0];
      const float* my = target.mean.ptr<float>(r);
      const float* xx = windowed.out[1];
      const float* yy = target.mean_sq.ptr<float>(r);
      const float* xy = windowed.out[2];
      float* dmu = grad_x ? d_mu.ptr<float>(r) : nullptr;
      float* dxx = grad_x ? d_exx.ptr<float>(r) : nullptr;
      float* dxy = grad_x ? d_exy.ptr<float>(r) : nullptr;
      if (grad_x)
        ssim_values<true>(mx, my, xx, yy, xy, width, c1, c2, g, values, dmu, dxx, dxy);
      else
        ssim_values<false>(mx, my, xx, yy, xy, width, c1, c2, g, values, nullptr, nullptr, nullptr);
      if (slot == kSumRows - 1 || r + 1 == rr.end())
        sum_rows(row_ssim.data(), slot + 1, width, &row_sum[r - slot]);
    }
  });
  if (grad_x) {
    // d/dx of window(x) is window^T = window; of window(x^2) adds 2x; of window(x y) adds y.
    grad_x->create(x.size(), x.type());
    tbb::parallel_for(tbb::blocked_range<int>(0, x.rows, 16), [&](const auto& rows) {
      WindowRows<3>& windowed = buffers.local();
      const auto source_rows = [&](int source) {
        return std::array<const float*, 3>{d_mu.ptr<float>(source), d_exx.ptr<float>(source),
                                           d_exy.ptr<float>(source)};
      };
      const auto value = [](int n, const std::array<const float*, 3>& p, int i) { return p[n][i]; };
      for (int r = rows.begin(); r < rows.end(); ++r) {
        window_row<3>(r, x.rows, channels, source_rows, value, windowed);
        const float *a = windowed.out[0], *b = windowed.out[1], *c = windowed.out[2];
        const float *px = x.ptr<float>(r), *py = y.ptr<float>(r);
        float* out = grad_x->ptr<float>(r);
        for (int i = 0; i < width; ++i) out[i] = a[i] + 2 * px[i] * b[i] + py[i] * c[i];
      }
    });
  }
  double sum = 0;
  for (double s : row_sum) sum += s;
  return sum / static_cast<double>(count);
}

double ssim(const cv::Mat& x, const cv::Mat& y, cv::Mat* grad_x) {
  require_ssim_inputs(x, y);
  return ssim(x, SsimTarget(y), grad_x);
}

}  // namespace gslift
