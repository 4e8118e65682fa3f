// Spherical harmonics against the 3DGS reference (Kerbl et al. 2023, eval_sh in utils/sh_utils.py
// of the INRIA code, the same polynomials and signs as gsplat): the basis at hand-computed
// directions, its normalisation, its gradient, and an INRIA PLY rendered against a per-pixel hand
// computation. A sign error in any basis function of degree 1 to 3 fails these tests.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "nodes/splat/ply_io.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/sh.hpp"
#include "tests/pinhole.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// The 3DGS constants: C0 = 1 / (2 sqrt(pi)), C1 = sqrt(3) / (2 sqrt(pi)), C2 and C3 as listed in
// the reference code (signs included).
constexpr double kC0 = 0.28209479177387814;
constexpr double kC1 = 0.4886025119029199;
constexpr double kC2[5] = {1.0925484305920792, -1.0925484305920792, 0.31539156525252005,
                           -1.0925484305920792, 0.5462742152960396};
constexpr double kC3[7] = {-0.5900435899266435, 2.890611442640554,   -0.4570457994644658,
                           0.3731763325901154,  -0.4570457994644658, 1.445305721320277,
                           -0.5900435899266435};

struct Direction {
  Eigen::Vector3d dir;
  double basis[16];
};

// The 16 basis values written out by hand from the reference polynomials:
//   degree 1: -C1 y, C1 z, -C1 x
//   degree 2: C2[0] xy, C2[1] yz, C2[2] (2zz - xx - yy), C2[3] xz, C2[4] (xx - yy)
//   degree 3: C3[0] y (3xx - yy), C3[1] xyz, C3[2] y (4zz - xx - yy), C3[3] z (2zz - 3xx - 3yy),
//             C3[4] x (4zz - xx - yy), C3[5] z (xx - yy), C3[6] x (xx - 3yy)
// On the axes most of them vanish and the others are a constant or twice one; the two oblique
// directions (every function non-zero) were evaluated in double.
const std::vector<Direction>& directions() {
  static const std::vector<Direction> table = {
      // +x: -C1, -C2[2], C2[4], -C3[4], C3[6].
      {{1, 0, 0}, {kC0, 0, 0, -kC1, 0, 0, -kC2[2], 0, kC2[4], 0, 0, 0, 0, -kC3[4], 0, kC3[6]}},
      // -x: the odd degrees change sign.
      {{-1, 0, 0}, {kC0, 0, 0, kC1, 0, 0, -kC2[2], 0, kC2[4], 0, 0, 0, 0, kC3[4], 0, -kC3[6]}},
      // +y: -C1, -C2[2], -C2[4], -C3[0], -C3[2].
      {{0, 1, 0}, {kC0, -kC1, 0, 0, 0, 0, -kC2[2], 0, -kC2[4], -kC3[0], 0, -kC3[2], 0, 0, 0, 0}},
      // -z: -C1, 2 C2[2], -2 C3[3].
      {{0, 0, -1}, {kC0, 0, -kC1, 0, 0, 0, 2 * kC2[2], 0, 0, 0, 0, 0, -2 * kC3[3], 0, 0, 0}},
      // +z.
      {{0, 0, 1}, {kC0, 0, kC1, 0, 0, 0, 2 * kC2[2], 0, 0, 0, 0, 0, 2 * kC3[3], 0, 0, 0}},
      // (1, 2, 3) / sqrt(14).
      {Eigen::Vector3d(1, 2, 3).normalized(),
       {0.2820947918, -0.2611690283, 0.3917535424, -0.1305845141, 0.1560783472, -0.4682350417,
        0.2928635963, -0.2341175208, -0.1170587604, 0.0225279689, 0.3310921732, -0.5409527810,
        0.0641157236, -0.2704763905, -0.2483191299, 0.1239038292}},
      // (-2, 1, -1) / sqrt(6).
      {Eigen::Vector3d(-2, 1, -1).normalized(),
       {0.2820947918, -0.1994711402, -0.1994711402, 0.3989422804, -0.3641828102, 0.1820914051,
        -0.1576957826, -0.3641828102, 0.2731371076, -0.4416211926, 0.3933623933, 0.0310980277,
        0.3300886329, -0.0621960554, -0.2950217950, 0.0802947623}},
  };
  return table;
}

}  // namespace

TEST_CASE("sh_basis of degrees 1 to 3 matches the 3DGS polynomials at hand-computed directions",
          "[splat][sh]") {
  for (const Direction& d : directions()) {
    for (int degree = 0; degree <= 3; ++degree) {
      INFO("direction " << d.dir.transpose() << ", degree " << degree);
      float basis[kMaxShCoeffs];
      std::fill(std::begin(basis), std::end(basis), 1234.f);  // what the degree must not touch
      sh_basis(degree, d.dir.cast<float>(), basis);
      const int used = (degree + 1) * (degree + 1);
      for (int k = 0; k < kMaxShCoeffs; ++k) {
        INFO("basis " << k);
        if (k < used)
          CHECK(basis[k] == Approx(d.basis[k]).margin(1e-7).epsilon(1e-6));
        else
          CHECK(basis[k] == 1234.f);
      }
    }
  }
}

TEST_CASE("sh_basis is orthonormal over the sphere", "[splat][sh]") {
  // Quadrature in z = cos(theta) (midpoint rule, 4000 rows) times phi (32 equal steps, exact for
  // the products of two degree-3 functions, trigonometric of degree 6 in phi): with the constants
  // above the Gram matrix is the identity.
  const int rows = 4000, columns = 32;
  Eigen::Matrix<double, 16, 16> gram = Eigen::Matrix<double, 16, 16>::Zero();
  const double pi = std::acos(-1.0);
  const double weight = (2.0 / rows) * (2.0 * pi / columns);
  for (int i = 0; i < rows; ++i) {
    const double z = -1.0 + (i + 0.5) * 2.0 / rows, r = std::sqrt(1.0 - z * z);
    for (int j = 0; j < columns; ++j) {
      const double phi = 2.0 * pi * j / columns;
      float basis[kMaxShCoeffs];
      sh_basis(3, Eigen::Vector3f(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)),
               basis);
      Eigen::Map<const Eigen::Matrix<float, 16, 1>> b(basis);
      gram += weight * b.cast<double>() * b.cast<double>().transpose();
    }
  }
  CHECK((gram - Eigen::Matrix<double, 16, 16>::Identity()).cwiseAbs().maxCoeff() < 1e-5);
}

TEST_CASE("sh_basis gradients match finite differences of the polynomials", "[splat][sh]") {
  const double h = 1e-3;
  for (const Direction& d : directions()) {
    float basis[kMaxShCoeffs];
    Eigen::Vector3f gradient[kMaxShCoeffs];
    sh_basis(3, d.dir.cast<float>(), basis, gradient);
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::Vector3d step = Eigen::Vector3d::Zero();
      step[axis] = h;
      float plus[kMaxShCoeffs], minus[kMaxShCoeffs];
      sh_basis(3, (d.dir + step).cast<float>(), plus);
      sh_basis(3, (d.dir - step).cast<float>(), minus);
      for (int k = 0; k < kMaxShCoeffs; ++k) {
        INFO("direction " << d.dir.transpose() << ", basis " << k << ", axis " << axis);
        CHECK(gradient[k][axis] == Approx((double(plus[k]) - minus[k]) / (2 * h)).margin(2e-4));
      }
    }
  }
}

namespace {

// Camera 2 units before `target`, looking along `dir` (camera z), any roll: the Gaussian at
// `target` is seen in direction `dir` and projects to the principal point.
Pose looking_at(const Eigen::Vector3d& target, const Eigen::Vector3d& dir) {
  const Eigen::Vector3d z = dir.normalized();
  const Eigen::Vector3d helper =
      std::abs(z.z()) < 0.9 ? Eigen::Vector3d(0, 0, 1) : Eigen::Vector3d(0, 1, 0);
  const Eigen::Vector3d x = z.cross(helper).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Pose pose;
  pose.R.row(0) = x;
  pose.R.row(1) = y;
  pose.R.row(2) = z;
  pose.t = -pose.R * (target - 2.0 * z);
  return pose;
}

}  // namespace

TEST_CASE("the INRIA degree-1 PLY renders the colours of a per-pixel hand computation",
          "[splat][sh]") {
  // tests/data/splat/inria_degree1.ply (make_inria_ply.py): property p of vertex i holds
  // 100 i + p, in the INRIA order x y z nx ny nz f_dc_0..2 f_rest_0..8 opacity scale_0..2
  // rot_0..3. f_rest is channel-major: coefficient k = 1..3 of channel c is f_rest_{3c + k - 1},
  // property 8 + 3c + k. Gaussian 0 sits at (0, 1, 2) with DC (6, 7, 8) and opacity logit 18
  // (alpha clamps at 0.99); Gaussian 1 at (100, 101, 102). Their log-scales (19..21 and
  // 119..121) overflow a float covariance, so the test makes them isotropic with scale 0.1: the
  // quaternions then do not matter, and everything the colour depends on is as shipped.
  GaussianModel model = read_ply(test::test_data("splat/inria_degree1.ply"));
  REQUIRE(model.size() == 2);
  REQUIRE(model.sh_degree == 1);
  const double scale = 0.1;
  std::fill(model.log_scales.begin(), model.log_scales.end(), float(std::log(scale)));

  // The fixture's values, by hand.
  auto property = [](int i, int p) { return 100.0 * i + p; };
  auto colour = [&](int i, const Eigen::Vector3d& dir) {
    Eigen::Vector3d c;
    for (int ch = 0; ch < 3; ++ch) {
      auto rest = [&](int k) { return property(i, 8 + 3 * ch + k); };
      const double raw = 0.5 + kC0 * property(i, 6 + ch) - kC1 * dir.y() * rest(1) +
                         kC1 * dir.z() * rest(2) - kC1 * dir.x() * rest(3);
      c[ch] = std::max(raw, 0.0);  // 3DGS clamps the SH colour at 0
    }
    return c;
  };
  const Eigen::Vector3d means[2] = {{property(0, 0), property(0, 1), property(0, 2)},
                                    {property(1, 0), property(1, 1), property(1, 2)}};
  auto opacity = [&](int i) { return 1.0 / (1.0 + std::exp(-property(i, 18))); };

  const Camera camera = test::centred_pinhole(64, 48, 60);
  RenderSettings settings;
  settings.background = Eigen::Vector3f(0.25f, 0.5f, 0.75f);

  // Gaussian 0 seen along the six axes and two oblique directions (none of which brings
  // Gaussian 1 into view, which the hand computation would handle as well).
  for (const Eigen::Vector3d& dir :
       {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(0, 1, 0),
        Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -1),
        Eigen::Vector3d(1, -2, 3).normalized(), Eigen::Vector3d(-2, 1, -1).normalized()}) {
    INFO("view direction " << dir.transpose());
    const Pose pose = looking_at(means[0], dir);
    const RenderOutput out = render(model, camera, pose, settings);

    // Per Gaussian: 2D mean and covariance s^2 J J^T + 0.3 (EWA with the 3DGS dilation and the
    // Jacobian's x/z, y/z clamped to 1.3 tan(fov / 2)), colour for the camera-to-mean direction.
    struct Seen {
      double depth, opacity;
      Eigen::Vector2d mean;
      Eigen::Matrix2d inverse_cov;
      Eigen::Vector3d colour;
    };
    std::vector<Seen> seen;
    const Eigen::Vector3d centre = pose.centre();
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector3d cam = pose.R * means[i] + pose.t;
      if (cam.z() < 0.01) continue;
      const double u = std::clamp(cam.x() / cam.z(), -1.3 * 32 / 60.0, 1.3 * 32 / 60.0);
      const double v = std::clamp(cam.y() / cam.z(), -1.3 * 24 / 60.0, 1.3 * 24 / 60.0);
      Eigen::Matrix<double, 2, 3> J;
      J << 60 / cam.z(), 0, -60 * u / cam.z(), 0, 60 / cam.z(), -60 * v / cam.z();
      const Eigen::Matrix2d cov =
          scale * scale * J * J.transpose() + 0.3 * Eigen::Matrix2d::Identity();
      seen.push_back({cam.z(),
                      opacity(i),
                      {60 * cam.x() / cam.z() + 32, 60 * cam.y() / cam.z() + 24},
                      cov.inverse(),
                      colour(i, (means[i] - centre).normalized())});
    }
    std::sort(seen.begin(), seen.end(),
              [](const Seen& a, const Seen& b) { return a.depth < b.depth; });
    REQUIRE(seen.size() >= 1);
    CHECK((seen[0].mean - Eigen::Vector2d(32, 24)).norm() < 1e-4);

    // Front-to-back blending per pixel: alpha = min(0.99, o exp(-0.5 d^T cov^-1 d)), skipped
    // below 1/255; C = sum colour alpha T + T_final background. (Gaussian 0's 1/255 ellipse,
    // 3.3 sigma or 10 pixels, lies inside the tiles of its 3-sigma square, so the tile rule
    // changes nothing here.) Pixels within float rounding of the 1/255 threshold are left out.
    int compared = 0, drawn = 0;
    double worst = 0;
    std::string worst_at;
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        double T = 1;
        Eigen::Vector3d expected = Eigen::Vector3d::Zero();
        bool borderline = false;
        for (const Seen& g : seen) {
          const Eigen::Vector2d d = g.mean - Eigen::Vector2d(x + 0.5, y + 0.5);
          const double alpha =
              std::min(0.99, g.opacity * std::exp(-0.5 * d.dot(g.inverse_cov * d)));
          borderline |= std::abs(alpha * 255.0 - 1.0) < 1e-3;
          if (alpha < 1.0 / 255.0) continue;
          expected += g.colour * alpha * T;
          T *= 1 - alpha;
        }
        expected += T * settings.background.cast<double>();
        if (borderline) continue;
        ++compared;
        drawn += T < 1;
        const size_t pix = size_t(y) * camera.width + x;
        for (int ch = 0; ch < 3; ++ch) {
          // Float against double: relative 1e-5, and 1e-5 absolute near 0.
          const double error = std::abs(out.rgb[pix * 3 + ch] - expected[ch]) /
                               std::max(1.0, std::abs(expected[ch]));
          if (error > worst) {
            worst = error;
            worst_at = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") channel " +
                       std::to_string(ch) + ": rendered " + std::to_string(out.rgb[pix * 3 + ch]) +
                       ", by hand " + std::to_string(expected[ch]);
          }
        }
      }
    INFO("largest difference at " << worst_at);
    CHECK(worst < 1e-5);
    CHECK(compared > camera.width * camera.height - 20);
    // Gaussian 0's footprint: sigma = sqrt(0.01 * 30^2 + 0.3) = 3.05 pixels, alpha >= 1/255 out to
    // 3.33 sigma, a disc of some 320 pixels.
    CHECK(drawn > 300);
  }
}
