// fusion.bayesian (paper 002 Algorithm 2): hand-computed products of two distributions.
#include "nodes/fusion/bayesian_fusion.hpp"

#include <catch2/catch.hpp>

#include "base/errors.hpp"

using namespace gslift;

namespace {

// A 3x1 view with the given per-pixel distributions over 3 classes.
SemanticView view3(std::vector<float> p) {
  SemanticView v;
  v.view = "v";
  v.probabilities = std::move(p);
  set_argmax(v, 3, 3, 1);
  return v;
}

}  // namespace

TEST_CASE("Bayesian fusion multiplies, normalises and takes the argmax", "[fusion]") {
  const SemanticView a = view3({0.5f, 0.3f, 0.2f, 0.8f, 0.1f, 0.1f, 1.f, 0.f, 0.f});
  const SemanticView b = view3({0.2f, 0.6f, 0.2f, 1 / 3.f, 1 / 3.f, 1 / 3.f, 0.f, 1.f, 0.f});
  const SemanticView f = fuse_bayesian(a, b, 3, 3, 1);
  // Pixel 0: (0.1, 0.18, 0.04) / 0.32.
  CHECK(f.probabilities[0] == Approx(0.3125));
  CHECK(f.probabilities[1] == Approx(0.5625));
  CHECK(f.probabilities[2] == Approx(0.125));
  CHECK(f.labels(0, 0) == 1);
  CHECK(f.confidence(0, 0) == Approx(0.5625));
  // Pixel 1: a uniform second source leaves the first one as it is.
  CHECK(f.probabilities[3] == Approx(0.8));
  CHECK(f.probabilities[4] == Approx(0.1));
  CHECK(f.labels(0, 1) == 0);
  // Pixel 2: two certain, contradicting sources: the mean (0.5, 0.5, 0), tie to the lowest id.
  CHECK(f.probabilities[6] == Approx(0.5));
  CHECK(f.probabilities[7] == Approx(0.5));
  CHECK(f.probabilities[8] == 0.f);
  CHECK(f.labels(0, 2) == 0);
}

TEST_CASE("a detector prior's label and confidence as a distribution", "[fusion]") {
  cv::Mat1i labels(1, 2);
  labels << 2, -1;
  cv::Mat1f confidence(1, 2);
  confidence << 0.7f, 0.f;
  const SemanticView v = label_confidence_view("v", labels, confidence, 4);
  CHECK(v.probabilities[0] == Approx(0.1));
  CHECK(v.probabilities[2] == Approx(0.7));
  CHECK(v.probabilities[4] == Approx(0.25));  // no prior: uniform
  CHECK(v.labels(0, 1) == -1);
  CHECK(v.confidence(0, 1) == Approx(0.25));
  CHECK_THROWS_AS(label_confidence_view("v", cv::Mat1i(1, 1, 4), cv::Mat1f(1, 1, 1.f), 4),
                  InputError);
}

TEST_CASE("Bayesian fusion rejects views of different sizes", "[fusion]") {
  const SemanticView a = view3({0.5f, 0.3f, 0.2f, 0.8f, 0.1f, 0.1f, 1.f, 0.f, 0.f});
  SemanticView b = a;
  b.probabilities.resize(6);
  CHECK_THROWS_AS(fuse_bayesian(a, b, 3, 3, 1), InputError);
}
