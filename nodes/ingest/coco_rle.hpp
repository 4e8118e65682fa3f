// COCO run-length encoding of binary masks, as pycocotools' maskApi.c writes it (SAM's
// "coco_rle" output mode). Runs go down the columns (column-major / Fortran order), alternate
// background and foreground, and start with background (a mask whose first pixel is set starts
// with a run of 0).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

namespace gslift {

// The runs of `mask` (nonzero = inside).
std::vector<uint32_t> rle_encode(const cv::Mat1b& mask);

// The mask (255 inside, 0 outside) of `counts` for an h x w image. Throws InputError starting
// with `where` when the counts do not sum to h * w.
cv::Mat1b rle_decode(const std::vector<uint32_t>& counts, int height, int width,
                     const std::string& where);

// maskApi.c rleToString / rleFrString: each count in 5-bit groups, least significant first,
// as characters 48 + (group | 0x20 when more groups follow); the sign is carried by bit 0x10 of
// the last group, and counts after the second are stored as the difference to the count two
// before them. Malformed strings throw InputError starting with `where`.
std::string rle_counts_to_string(const std::vector<uint32_t>& counts);
std::vector<uint32_t> rle_counts_from_string(const std::string& s, const std::string& where);

// A COCO RLE JSON record {"size": [h, w], "counts": "<string>" | [int, ...]} decoded.
cv::Mat1b rle_decode_json(const nlohmann::json& rle, const std::string& where);

}  // namespace gslift
