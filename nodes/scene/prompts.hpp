// Prompts of promptable 3D segmentation (SAGA, paper 001 §4.4): clicks, scribbles or masks given
// in one view of the capture, each naming the object it asks for.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "base/port_type.hpp"
#include "param/param_table.hpp"

namespace gslift {

// point: positive / negative pixels; scribble: positive / negative strokes (polylines through
// the listed pixels); mask: a binary mask (dense hint, K-means queries); sam: a reference mask
// as SAM would return it (masked average pooling, with the 90% check).
enum class PromptKind { Point, Scribble, Mask, Sam };
const EnumNames<PromptKind>& prompt_kind_names();  // point, scribble, mask, sam

struct Prompt {
  std::string name;  // the object asked for; masks and files carry it
  PromptKind kind = PromptKind::Point;
  std::string view;                 // view name in the capture
  std::vector<cv::Point> positive;  // pixels (x right, y down); scribble: stroke vertices
  std::vector<cv::Point> negative;
  cv::Mat1b mask;  // mask and sam prompts: 255 = the object, view-sized
};

struct PromptSet {
  std::vector<Prompt> prompts;
  // Where the prompts were answered by FlashSplat's vote (inference.prompt_lift): per prompt, per
  // Gaussian of that model, (A_1 - A_0) / |(A_0, A_1)|, how much more of the Gaussian's blend
  // weight over the voting views fell inside the prompt's masks than outside, in [-1, 1]; 0 where
  // no voting view sees it. Empty otherwise.
  std::vector<std::vector<float>> vote_balance;
};

GSLIFT_PORT_TYPE(PromptSet, "PromptSet");

}  // namespace gslift
