// fusion.cluster_smoothing on a hand-built clustering, and the supervoxel over-segmentation that
// gives the clusters in the graph.
#include "nodes/fusion/cluster_smoothing.hpp"

#include <set>

#include <catch2/catch.hpp>

#include "base/errors.hpp"

#include "nodes/fusion/supervoxels.hpp"
#include "tests/pinhole.hpp"

using namespace gslift;

TEST_CASE("cluster smoothing: majority label and the mean distribution of its pixels", "[fusion]") {
  // 4x2 view, 2 classes. Clusters:   labels:       distributions (p0, p1):
  //   0 0 0 1                        0 0 1 1       (.9 .1) (.7 .3) (.2 .8) (.4 .6)
  //   0 1 1 -1                       0 -1 1 0      (.6 .4) (.5 .5) (.3 .7) (.8 .2)
  SemanticView v;
  v.view = "v";
  v.probabilities = {.9f, .1f, .7f, .3f, .2f, .8f, .4f, .6f,
                     .6f, .4f, .5f, .5f, .3f, .7f, .8f, .2f};
  v.labels = (cv::Mat1i(2, 4) << 0, 0, 1, 1, 0, -1, 1, 0);
  v.confidence = cv::Mat1f(2, 4, 0.f);
  const cv::Mat1i clusters = (cv::Mat1i(2, 4) << 0, 0, 0, 1, 0, 1, 1, -1);
  const ClusterSmoothingResult r = smooth_clusters(v, clusters, 2);
  CHECK(r.clusters == 2);
  // Cluster 0: labels 0, 0, 1, 0 -> 0; mean of (.9 .1), (.7 .3), (.6 .4) = (.7333, .2667).
  for (int p : {0, 1, 2, 4}) {
    CHECK(r.smoothed.labels(p / 4, p % 4) == 0);
    CHECK(r.smoothed.probabilities[2 * p] == Approx(2.2 / 3));
    CHECK(r.smoothed.confidence(p / 4, p % 4) == Approx(2.2 / 3));
  }
  // Cluster 1: labels 1, -1 (no vote), 1 -> 1; mean of (.4 .6), (.3 .7) = (.35, .65); the pixel
  // without a label takes it too.
  for (int p : {3, 5, 6}) {
    CHECK(r.smoothed.labels(p / 4, p % 4) == 1);
    CHECK(r.smoothed.probabilities[2 * p + 1] == Approx(0.65));
  }
  // Outside every cluster: unchanged.
  CHECK(r.smoothed.labels(1, 3) == 0);
  CHECK(r.smoothed.probabilities[15] == Approx(0.2));
  CHECK(r.changed == 2);  // pixel 2 (1 -> 0) and pixel 5 (-1 -> 1)
  CHECK_THROWS_AS(smooth_clusters(v, cv::Mat1i(2, 3, 0), 2), InputError);
}

TEST_CASE("supervoxels do not cross a depth step and cover the valid pixels", "[fusion]") {
  // 64x48 view of one colour: left half a wall 2 m away, right half 3 m away, a hole in a corner.
  const Camera cam = test::centred_pinhole(64, 48, 50);
  cv::Mat1f depth(48, 64, 2.f);
  depth(cv::Rect(32, 0, 32, 48)).setTo(3.f);
  depth(cv::Rect(0, 0, 4, 4)).setTo(0.f);
  const cv::Mat rgb(48, 64, CV_8UC3, cv::Scalar(120, 80, 60));
  SupervoxelOptions o;
  o.seed_spacing = 8;
  const cv::Mat1i c = oversegment_rgbd(rgb, depth, cam, o);
  std::set<int> left, right;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      if (depth(y, x) == 0) {
        CHECK(c(y, x) == -1);
        continue;
      }
      REQUIRE(c(y, x) >= 0);
      (x < 32 ? left : right).insert(c(y, x));
    }
  for (int k : left) CHECK(right.count(k) == 0);
  // Seeds every 8 pixels: about 4 x 6 clusters per half (they are over-segments, not the halves).
  CHECK(left.size() >= 12);
  CHECK(right.size() >= 12);
  // The same input gives the same clusters.
  CHECK(cv::countNonZero(oversegment_rgbd(rgb, depth, cam, o) != c) == 0);
}
