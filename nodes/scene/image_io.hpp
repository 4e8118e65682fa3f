// Reading and writing the image files of a capture (docs/capture_format.md): RGB, depth priors,
// label maps and float maps. The synthetic generator writes with these and ingest reads with
// them, so both sides agree on channel order, bit depth and units. Every reader throws
// InputError naming the file; every writer goes through write_atomically.
#pragma once

#include <filesystem>

#include <opencv2/core.hpp>

namespace gslift {

// The image decoded with cv::imread `flags` (as stored by default). Refused with InputError naming
// the file: a path that is not a regular file, a file that is not a PNG, JPEG, TIFF, BMP, WebP or
// OpenEXR image, one whose header (image_header.hpp) declares more than kMaxImagePixels
// (camera.hpp; checked before decoding), and anything OpenCV cannot decode. Every
// reader below starts here, and so does every other image read of gslift.
cv::Mat read_image(const std::filesystem::path& path, int flags = -1 /* IMREAD_UNCHANGED */);

// CV_8UC3 in RGB channel order. Grey images are replicated to three channels, 16-bit images are
// reduced to 8 bits, and an alpha channel is composited onto `background` (RGB; NeRF's Blender
// scenes are rendered for a white background, hence the default).
cv::Mat read_rgb(const std::filesystem::path& path, const cv::Scalar& background = {255, 255, 255});

// The alpha channel of an RGBA image as CV_8UC1, or an empty Mat when the image has none (the
// NeRF synthetic scenes use it as an exact foreground mask).
cv::Mat read_alpha(const std::filesystem::path& path);

// CV_32FC1 metres, 0 = invalid. A 16-bit image is divided by `scale` (1000 for millimetres,
// 6553.5 for Replica); a float32 TIFF/EXR is taken as metres and `scale` is ignored. Negative and
// non-finite values become 0 (invalid). Anything else (8-bit, colour) is rejected.
cv::Mat read_depth(const std::filesystem::path& path, double scale);

// CV_32SC1 ids. Accepts 16-bit single-channel PNG/TIFF (and 32-bit integer TIFF); an 8-bit map
// is accepted with a warning (it cannot hold more than 255 ids) unless `accept_8bit` is false,
// as for the ground truth of a gslift capture, whose layout requires 16 bits; colour images are
// rejected.
cv::Mat read_label_map(const std::filesystem::path& path, bool accept_8bit = true);

// A float32 map as stored (CV_32FC1 or CV_32FC3), e.g. gt/depth and gt/normal TIFFs.
cv::Mat read_float_tiff(const std::filesystem::path& path);

// `rgb` is CV_8UC3 in RGB order; written as an 8-bit PNG.
void write_rgb_png(const std::filesystem::path& path, const cv::Mat& rgb);
// `depth` is CV_32FC1 metres; written as 16-bit millimetres (read back with scale 1000).
// Values that do not fit (negative, non-finite, above 65.535 m) are written as 0 = invalid.
void write_depth_png_mm(const std::filesystem::path& path, const cv::Mat& depth);
// `depth` is CV_32FC1 metres, written losslessly as a float32 TIFF.
void write_depth_tiff(const std::filesystem::path& path, const cv::Mat& depth);
// `labels` is CV_32SC1 with ids in [0, 65535]; written as a 16-bit PNG. Throws InputError naming
// the file when an id does not fit.
void write_label_png16(const std::filesystem::path& path, const cv::Mat& labels);
// `map` is CV_32FC1 or CV_32FC3, written losslessly as a float32 TIFF.
void write_float_tiff(const std::filesystem::path& path, const cv::Mat& map);

}  // namespace gslift
