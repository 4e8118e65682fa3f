#include "nodes/eval/instance_hungarian.hpp"

#include <catch2/catch.hpp>

#include "nodes/eval/hungarian.hpp"

using namespace gslift;

// Two 2x2 images (ids row-major):
//   image 1: GT [1 1; 2 0], prediction [5 5; 5 0]
//   image 2: GT [1 1; 0 0], prediction [7 7; 0 0]
// Per image IoU = n_gp / (a_g + a_p - n_gp):
//   image 1: (1,5) 2/(2+3-2) = 2/3, (2,5) 1/(1+3-1) = 1/3, (0,0) 1
//   image 2: (1,7) 1, (0,0) 1
// Averaged over the images where the GT label is present (0 and 1: both; 2: image 1 only):
//        p0   p5    p7
//   g0 [ 1    0     0   ]
//   g1 [ 0    1/3   1/2 ]
//   g2 [ 0    1/3   0   ]
// The best one-to-one matching: g0-p0, g1-p7, g2-p5 (1 + 1/2 + 1/3 beats 1 + 1/3 + 0).
// mIoU = 11/18; hits (IoU > 0.5, strict, so g1's 0.5 is no hit) = 1: precision = recall = 1/3.
TEST_CASE("score_instances_hungarian: Gaga's eval.py on a hand-computed case") {
  const std::vector<cv::Mat1i> gt{(cv::Mat1i(2, 2) << 1, 1, 2, 0), (cv::Mat1i(2, 2) << 1, 1, 0, 0)};
  const std::vector<cv::Mat1i> pred{(cv::Mat1i(2, 2) << 5, 5, 5, 0),
                                    (cv::Mat1i(2, 2) << 7, 7, 0, 0)};
  const InstanceScores s = score_instances_hungarian(gt, pred);
  CHECK(s.gt_labels == 3);
  CHECK(s.pred_labels == 3);
  CHECK(s.gt_ids == std::vector<int>{0, 1, 2});
  CHECK(s.matched_pred == std::vector<int>{0, 7, 5});
  CHECK(s.matched_iou[0] == Approx(1.0));
  CHECK(s.matched_iou[1] == Approx(0.5));
  CHECK(s.matched_iou[2] == Approx(1.0 / 3));
  CHECK(s.miou == Approx(11.0 / 18));
  CHECK(s.hits == 1);
  CHECK(s.precision == Approx(1.0 / 3));
  CHECK(s.recall == Approx(1.0 / 3));
}

// More predicted labels than GT ones: precision divides by all of them. GT [1 1 2 2] against
// prediction [3 4 5 5]: g1 matches 3 or 4 (IoU 1/2), g2 matches 5 (IoU 1); one hit;
// precision 1/3, recall 1/2, mIoU 3/4. Fewer predicted labels: a GT label left over gets
// a padding column and IoU 0.
TEST_CASE("score_instances_hungarian: rectangular cases") {
  auto s = score_instances_hungarian({(cv::Mat1i(1, 4) << 1, 1, 2, 2)},
                                     {(cv::Mat1i(1, 4) << 3, 4, 5, 5)});
  CHECK(s.miou == Approx(0.75));
  CHECK(s.hits == 1);
  CHECK(s.precision == Approx(1.0 / 3));
  CHECK(s.recall == Approx(0.5));
  s = score_instances_hungarian({(cv::Mat1i(1, 4) << 1, 1, 2, 2)},
                                {(cv::Mat1i(1, 4) << 3, 3, 3, 3)});
  CHECK(s.miou == Approx(0.25));  // one of the two GT labels gets IoU 1/2, the other padding
  CHECK(s.hits == 0);
  CHECK((s.matched_pred[0] == -1 || s.matched_pred[1] == -1));
  CHECK_THROWS(score_instances_hungarian({cv::Mat1i::zeros(2, 2)}, {cv::Mat1i::zeros(2, 3)}));
}

// matches.csv names each ground-truth instance's class from the capture: the hand-computed case
// above, where instance 1 is of class 3 ("table, instrument": a name that needs quoting) and
// instance 2 has no class in the capture; label 0 is the background.
TEST_CASE("instance_matches_csv: the class of each ground-truth instance") {
  const InstanceScores s =
      score_instances_hungarian({(cv::Mat1i(2, 2) << 1, 1, 2, 0), (cv::Mat1i(2, 2) << 1, 1, 0, 0)},
                                {(cv::Mat1i(2, 2) << 5, 5, 5, 0), (cv::Mat1i(2, 2) << 7, 7, 0, 0)});
  Capture capture;
  capture.classes = {{0, "background"}, {3, "table, instrument"}};
  capture.instance_class = {{1, 3}};
  CHECK(instance_matches_csv(s, capture) ==
        "gt_label,class,matched_pred,iou\n"
        "0,,0,1.000000\n"
        "1,\"table, instrument\",7,0.500000\n"
        "2,,5,0.333333\n");
  capture.instance_class[2] = 9;  // a class id the vocabulary lacks: written as the id
  CHECK(instance_matches_csv(s, capture).find("\n2,9,5,") != std::string::npos);
}

// The assignment's total against brute force over every permutation of a 4x4 matrix.
TEST_CASE("max_score_assignment: optimal against brute force") {
  Eigen::MatrixXd m(4, 4);
  m << 7, 53, 183, 439, 497, 383, 563, 79, 627, 343, 773, 959, 447, 283, 463, 29;
  const std::vector<int> match = max_score_assignment(m);
  double got = 0;
  for (int r = 0; r < 4; ++r) got += m(r, match[r]);
  std::vector<int> perm{0, 1, 2, 3};
  double best = 0;
  do {
    double s = 0;
    for (int r = 0; r < 4; ++r) s += m(r, perm[r]);
    best = std::max(best, s);
  } while (std::next_permutation(perm.begin(), perm.end()));
  CHECK(got == best);
  // 2 rows, 3 columns: distinct columns, best total 9 + 8.
  Eigen::MatrixXd r(2, 3);
  r << 9, 9, 1, 1, 8, 2;
  CHECK(max_score_assignment(r) == std::vector<int>{0, 1});
}
