// fusion.render_semantics: per-Gaussian class distributions and the leftover transmittance.
#include "nodes/fusion/render_semantics.hpp"

#include <catch2/catch.hpp>

#include "base/errors.hpp"

using namespace gslift;

TEST_CASE("per-Gaussian class distributions from instance labels", "[fusion]") {
  RenderSemanticsOptions o;
  o.instance_confidence = 0.7f;
  o.background_confidence = 0.9f;
  // Gaussians: instance 0 (class 2), unassigned, instance 1 (a label that is no class).
  const std::vector<float> p = gaussian_class_probabilities({0, -1, 1}, {2, -1}, 3, o);
  REQUIRE(p.size() == 9);
  CHECK(p[0] == Approx(0.15));
  CHECK(p[2] == Approx(0.7));
  CHECK(p[3] == Approx(0.9));  // background, class 0
  CHECK(p[4] == Approx(0.05));
  CHECK(p[6] == Approx(1 / 3.0));  // uniform
  CHECK_THROWS_AS(gaussian_class_probabilities({2}, {2, -1}, 3, o), InputError);
}

TEST_CASE("the transmittance left at a pixel goes to the background distribution", "[fusion]") {
  RenderSemanticsOptions o;
  o.background_confidence = 0.8f;
  // Two pixels: one covered 60% by a Gaussian saying (0.1 0.1 0.8), one not covered at all.
  const std::vector<float> blend = {0.06f, 0.06f, 0.48f, 0.f, 0.f, 0.f};
  const SemanticView v = semantics_from_blend("v", blend, background_distribution(3, o), 3, 2, 1);
  CHECK(v.probabilities[0] == Approx(0.06 + 0.4 * 0.8));
  CHECK(v.probabilities[1] == Approx(0.06 + 0.4 * 0.1));
  CHECK(v.probabilities[2] == Approx(0.48 + 0.4 * 0.1));
  CHECK(v.labels(0, 0) == 2);
  CHECK(v.confidence(0, 0) == Approx(0.52));
  CHECK(v.probabilities[3] == Approx(0.8));
  CHECK(v.labels(0, 1) == 0);
}

TEST_CASE("a vocabulary given by the user stands in for the capture's ground-truth classes",
          "[fusion]") {
  Capture capture;
  capture.name = "mine";  // no gt/classes.yaml
  CHECK_THROWS_AS(semantic_classes(capture), InputError);
  CHECK(semantic_classes(capture, {"operating table", "surgeon"}) ==
        std::vector<std::string>{"background", "operating table", "surgeon"});
  capture.classes = {{1, "patient"}};
  CHECK(semantic_classes(capture, {}) == std::vector<std::string>{"background", "patient"});
  // Labels match case-insensitively, as for the capture's classes.
  CHECK(class_index(semantic_classes(capture, {"Surgeon"}), "surgeon") == 1);
}
