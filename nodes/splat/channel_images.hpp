// Displayable 8-bit pictures of rendered channels, for splat.render and the benchmark figures.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/splat/rasterizer.hpp"

namespace gslift {

// The channel names splat.render accepts.
const std::vector<std::string>& image_channels();  // rgb, depth, normal, alpha, features

// Sets the RenderSettings flag of a channel name; throws std::invalid_argument for an unknown one.
void request_channel(RenderSettings& settings, const std::string& channel);

// CV_8UC3 in RGB order for every channel:
//   rgb      clamped to [0,1] and scaled to 255;
//   depth    grey, 0 at the nearest rendered depth and 255 at the farthest (no depth = black);
//   normal   world-space unit normal n mapped to (n + 1) / 2 (no normal = black);
//   alpha    grey, accumulated opacity x 255;
//   features the first three feature channels, each min-max normalised over the image (an image
//            with fewer channels repeats the last one; none = black).
// The channel must have been rendered into `out`.
cv::Mat channel_image(const RenderOutput& out, const std::string& channel);

// What the colours of a channel's picture mean, as above, for its caption ("depth: grey, black
// nearest to white farthest; black where nothing was drawn").
std::string channel_meaning(const std::string& channel);

}  // namespace gslift
