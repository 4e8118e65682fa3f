// A view's rendered masks registered to its photo [gslift addition, issue 28]. Where a capture's
// written pose of a view is off (a rig's drifting calibration; the embedded OR's `hard` preset
// perturbs every pose by 0.5 degrees and 2 cm), the model rendered at that pose lies a few pixels
// off the photo, and so does every mask rendered there: a 5-pixel shift costs a small object half
// its IoU. The 2D translation that best registers the render to the photo is found by ECC image
// alignment (Evangelidis and Psarakis, PAMI 2008; OpenCV's findTransformECC; docs/references.md)
// and applied to the masks when it raises the correlation enough to tell a real offset from the
// render's own imperfections (on captures without pose noise the gain stays below 0.0013).
// Rotation and translation of the camera move points at different depths differently; a full
// pose search on the render's correlation drifted far beyond the noise (docs/saga.md), the 2D
// translation did not.
#pragma once

#include <opencv2/core.hpp>

namespace gslift {

struct PhotoAlignment {
  double shift_x = 0, shift_y = 0;  // pixels: the photo's content sits at the render's + shift
  double correlation_before = 0;    // ECC correlation of the (5x5 Gaussian-blurred) gray images
  double correlation_after = 0;     // ... with the render shifted; = before where ECC failed
  bool applied = false;             // after - before >= the min_gain asked for
};

// Registers `render` to `photo` (single-channel float images of the same size, any range) by a
// 2D translation; applied when it raises the correlation by at least `min_gain`. Throws
// std::invalid_argument on images of different sizes.
PhotoAlignment align_render_to_photo(const cv::Mat1f& render, const cv::Mat1f& photo,
                                     double min_gain);

// `image` (a mask or a map rendered at the view's pose, any type) moved by the alignment's shift
// when it was applied (nearest pixel, 0 where it comes from outside the image); otherwise a copy.
cv::Mat align_image(const cv::Mat& image, const PhotoAlignment& alignment);

}  // namespace gslift
