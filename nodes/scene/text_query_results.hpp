// What text queries answered (inference.text_query, LangOR §1.3 "Retrieval"), per query and per
// view: everything eval.langor needs to score them against the ground truth.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "base/port_type.hpp"

namespace gslift {

struct TextQueryResults {
  std::vector<std::string> queries;
  std::vector<std::vector<int>> instances;  // per query: the selected instances
  std::vector<Eigen::VectorXf> relevancy;   // per query: relevancy of every instance
  // Per query: the class of the closed-set vocabulary it lands on
  // (nodes/scene/vocabulary_match.hpp) and the cosine it lands with; "" and the nearest class's
  // cosine when none is near.
  std::vector<std::string> query_classes;
  std::vector<float> query_class_scores;
  struct ViewAnswers {
    std::string view;                  // view name in the capture
    std::vector<cv::Mat1b> masks;      // per query, 255 = selected
    std::vector<cv::Mat1f> relevancy;  // per query, per-pixel relevancy in [0, 1]
  };
  std::vector<ViewAnswers> views;
};

GSLIFT_PORT_TYPE(TextQueryResults, "TextQueryResults");

}  // namespace gslift
