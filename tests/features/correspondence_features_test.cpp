// SAGA's correspondence features on the two-group scene: pixels of one mask pull their Gaussians'
// features together, pixels of different masks (K = -1) push them apart.
#include "nodes/features/correspondence_features.hpp"

#include <tbb/global_control.h>
#include <Eigen/Core>

#include "base/errors.hpp"
#include "tests/features/two_groups.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

Eigen::VectorXd feature(const GaussianModel& m, int g) {
  Eigen::VectorXd f(m.feature_dim);
  for (int c = 0; c < m.feature_dim; ++c) f(c) = m.features[size_t(g) * m.feature_dim + c];
  return f;
}

CorrespondenceOptions small_options() {
  CorrespondenceOptions o;
  o.iterations = 150;
  o.dim = 8;
  o.lr = 2e-2;
  o.pixels_per_iteration = 128;
  o.seed = 3;
  return o;
}

}  // namespace

TEST_CASE("correspondence features separate the masks' Gaussians") {
  test::TwoGroups s = test::two_groups();
  const CorrespondenceResult r =
      train_correspondence_features(s.model, s.capture, s.masks, small_options());
  CHECK(r.views == 2);  // the held-out view's mask is ignored
  CHECK(r.masks == 4);
  CHECK(r.loss_end < r.loss_start - 0.5);
  CHECK(r.loss_end < -0.8);  // -1 is every pair perfectly aligned or opposed
  double within = 0, across = 0;
  int nw = 0, na = 0;
  for (size_t i = 0; i < s.group.size(); ++i)
    for (size_t j = i + 1; j < s.group.size(); ++j) {
      const Eigen::VectorXd a = feature(r.model, int(i)), b = feature(r.model, int(j));
      const double c = a.dot(b) / (a.norm() * b.norm());
      (s.group[i] == s.group[j] ? within : across) += c;
      (s.group[i] == s.group[j] ? nw : na) += 1;
    }
  CHECK(within / nw > 0.9);
  CHECK(across / na < -0.5);
}

TEST_CASE("correspondence features are the same at any thread count") {
  test::TwoGroups s = test::two_groups();
  CorrespondenceOptions o = small_options();
  o.iterations = 20;
  o.views_per_iteration = 3;
  std::vector<float> one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = train_correspondence_features(s.model, s.capture, s.masks, o).model.features;
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = train_correspondence_features(s.model, s.capture, s.masks, o).model.features;
  }
  CHECK(one == two);
}

TEST_CASE("correspondence features refuse captures without usable masks") {
  test::TwoGroups s = test::two_groups();
  MaskSet none;
  CHECK_THROWS_AS(train_correspondence_features(s.model, s.capture, none, small_options()),
                  InputError);
}
