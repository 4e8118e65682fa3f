// Labelled 2D boxes per view, e.g. the N rounds of VLM grounding answers, or their clustered
// representatives. Boxes are XYXY in image pixels (pixel-corner convention, see camera.hpp).
#pragma once

#include <string>
#include <vector>

#include "base/port_type.hpp"

namespace gslift {

struct Box {
  float x1 = 0, y1 = 0, x2 = 0, y2 = 0;
  std::string label;
  float score = 1.f;
  int round = 0;  // which VLM round produced it (0-based)
  // Clustered boxes only: how many rounds support the cluster, and the index of this box in the
  // round's answer (links it to the SAM mask prompted with it). -1 when unknown.
  int support = 1;
  int source_index = -1;

  float width() const { return x2 - x1; }
  float height() const { return y2 - y1; }
  float area() const { return width() > 0 && height() > 0 ? width() * height() : 0.f; }
};

float iou(const Box& a, const Box& b);

struct ViewBoxes {
  std::string view;  // view name in the capture
  int rounds = 0;    // number of rounds asked (some may have produced no box)
  std::vector<Box> boxes;
};

struct BoxSet {
  std::vector<ViewBoxes> views;  // in capture view order
};

GSLIFT_PORT_TYPE(BoxSet, "BoxSet");

}  // namespace gslift
