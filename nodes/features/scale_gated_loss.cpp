#include "nodes/features/scale_gated_loss.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "base/random.hpp"

namespace gslift {

Eigen::MatrixXf scale_gated_pair_weights(const std::vector<float>& area) {
  const Eigen::Index n = static_cast<Eigen::Index>(area.size());
  const Eigen::Map<const Eigen::VectorXf> m(area.data(), n);
  Eigen::MatrixXf prod = m * m.transpose();
  const float top = prod.maxCoeff();
  Eigen::MatrixXf w =
      prod.unaryExpr([&](float x) { return std::max(top / (x == 0 ? 1e10f : x), 1.f); });
  const float lo = w.minCoeff(), hi = w.maxCoeff();
  if (hi <= lo) return Eigen::MatrixXf::Ones(n, n);
  return ((w.array() - lo) / (hi - lo) * 9.f + 1.f).matrix();
}

ScaleGatedLoss scale_gated_loss(const Eigen::MatrixXf& f, const std::vector<Eigen::MatrixXf>& gt,
                                const std::vector<float>& scales, const Eigen::MatrixXf& w,
                                const std::vector<float>& gate, double norm_weight,
                                uint64_t pair_seed) {
  const Eigen::Index n = f.rows(), d = f.cols();
  const int ns = static_cast<int>(gt.size());
  if (n < 2 || ns < 1 || scales.size() != gt.size() || gate.size() != size_t(2 * d) ||
      w.rows() != n || w.cols() != n)
    throw std::invalid_argument("scale_gated_loss: inconsistent sizes");
  // Gates, gated normalised features and correlations per scale.
  std::vector<Eigen::RowVectorXf> g(ns);
  std::vector<Eigen::MatrixXf> u(ns), corr(ns);
  std::vector<Eigen::VectorXf> gated_norm(ns);
  for (int k = 0; k < ns; ++k) {
    g[k].resize(d);
    for (Eigen::Index c = 0; c < d; ++c)
      g[k](c) = 1.f / (1.f + std::exp(-(gate[c] * scales[k] + gate[d + c])));
    const Eigen::MatrixXf gated = f.array().rowwise() * g[k].array();
    gated_norm[k] = gated.rowwise().norm();
    u[k] = gated;
    for (Eigen::Index p = 0; p < n; ++p)
      u[k].row(p) = gated_norm[k](p) > 1e-12f ? (gated.row(p) / gated_norm[k](p)).eval()
                                              : Eigen::RowVectorXf::Zero(d).eval();
    corr[k] = u[k] * u[k].transpose();
  }
  // Pair sets, as the code builds them over the full P x P matrix.
  Eigen::MatrixXf sum0 = Eigen::MatrixXf::Zero(n, n);
  for (const auto& m : gt) sum0 += m;
  long consistent_pos = 0, consistent_neg = 0, inconsistent = 0;
  for (Eigen::Index q = 0; q < n; ++q)
    for (Eigen::Index p = 0; p < n; ++p) {
      if (sum0(p, q) == 0)
        ++consistent_neg;
      else if (sum0(p, q) == ns)
        ++consistent_pos;
      else
        ++inconsistent;
    }
  const double sampled = inconsistent / 2.0;
  const double rate_pos = consistent_pos ? sampled / consistent_pos : 0;
  const double rate_neg = consistent_neg ? sampled / consistent_neg : 0;
  RandomStream rng(pair_seed);
  // coef(p, q) = dL/dcorr_k(p, q) / (the mean's count), filled after the counts are known.
  std::vector<std::pair<Eigen::Index, Eigen::Index>> pos, neg;
  // Column by column (q), rows p < q: the matrices are column-major, so every read is sequential.
  for (Eigen::Index q = 1; q < n; ++q)
    for (Eigen::Index p = 0; p < q; ++p) {
      const double r = rng.uniform();
      const bool incons = sum0(p, q) != 0 && sum0(p, q) != ns;
      bool hard_pos = false, hard_neg = false;
      for (int k = 0; k < ns; ++k) {
        hard_pos |= gt[k](p, q) == 1 && corr[k](p, q) < 0.75f;
        hard_neg |= gt[k](p, q) == 0 && corr[k](p, q) > 0.5f;
      }
      if (incons || hard_pos || (sum0(p, q) == ns && r < rate_pos)) pos.emplace_back(p, q);
      if (incons || hard_neg || (sum0(p, q) == 0 && r < rate_neg)) neg.emplace_back(p, q);
    }
  ScaleGatedLoss out;
  out.positive_pairs = static_cast<int>(pos.size());
  out.negative_pairs = static_cast<int>(neg.size());
  std::vector<Eigen::MatrixXf> coef(ns, Eigen::MatrixXf::Zero(n, n));
  double loss = 0;
  if (!pos.empty()) {
    const double count = double(ns) * pos.size();
    for (int k = 0; k < ns; ++k)
      for (const auto& [p, q] : pos) {
        const float c = -w(p, q) * gt[k](p, q);
        loss += c * corr[k](p, q) / count;
        coef[k](p, q) += static_cast<float>(c / count);
      }
  }
  if (!neg.empty()) {
    const double count = double(ns) * neg.size();
    for (int k = 0; k < ns; ++k)
      for (const auto& [p, q] : neg) {
        const float c = w(p, q) * (1.f - gt[k](p, q));
        if (corr[k](p, q) <= 0 || c == 0) continue;
        loss += c * corr[k](p, q) / count;
        coef[k](p, q) += static_cast<float>(c / count);
      }
  }
  // The rendered-feature-norm regulariser.
  const Eigen::VectorXf norm = f.rowwise().norm();
  const double mean_norm = norm.mean();
  loss += norm_weight * (1 - mean_norm) * (1 - mean_norm);
  out.loss = loss;

  out.grad_features = Eigen::MatrixXf::Zero(n, d);
  out.grad_gate = Eigen::VectorXf::Zero(2 * d);
  for (int k = 0; k < ns; ++k) {
    // corr(p, q) = <u_p, u_q> for p < q: dL/du = (C + C^T) u, as two products (no transposed
    // copy of C).
    Eigen::MatrixXf du = coef[k] * u[k];
    du.noalias() += coef[k].transpose() * u[k];
    Eigen::RowVectorXf dg = Eigen::RowVectorXf::Zero(d);
    for (Eigen::Index p = 0; p < n; ++p) {
      if (gated_norm[k](p) <= 1e-12f) continue;
      const float along = du.row(p).dot(u[k].row(p));
      const Eigen::RowVectorXf dgated = (du.row(p) - along * u[k].row(p)) / gated_norm[k](p);
      out.grad_features.row(p) += (dgated.array() * g[k].array()).matrix();
      dg += (dgated.array() * f.row(p).array()).matrix();
    }
    // g = sigmoid(a s + b): dg/d(a s + b) = g (1 - g).
    const Eigen::RowVectorXf da = (dg.array() * g[k].array() * (1.f - g[k].array())).matrix();
    out.grad_gate.head(d) += (da * scales[k]).transpose();
    out.grad_gate.tail(d) += da.transpose();
  }
  const float dnorm = static_cast<float>(-2 * norm_weight * (1 - mean_norm) / n);
  for (Eigen::Index p = 0; p < n; ++p)
    if (norm(p) > 1e-12f) out.grad_features.row(p) += dnorm * f.row(p) / norm(p);
  return out;
}

}  // namespace gslift
