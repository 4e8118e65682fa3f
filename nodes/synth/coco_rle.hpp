// COCO run-length encoding of a binary mask, as SAM's automatic mask generator writes it
// (output_mode "coco_rle"): runs over the column-major pixel order, starting with a run of zeros,
// compressed into pycocotools' ASCII string form.
#pragma once

#include <string>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

namespace gslift::synth {

// The compressed "counts" string of pycocotools' rleToString.
std::string coco_rle_counts(const cv::Mat1b& mask);
// {"size": [height, width], "counts": "<compressed>"}; a pixel is inside when nonzero.
nlohmann::json coco_rle(const cv::Mat1b& mask);

}  // namespace gslift::synth
