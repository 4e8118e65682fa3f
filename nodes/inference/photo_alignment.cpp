#include "nodes/inference/photo_alignment.hpp"

#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace gslift {

namespace {

constexpr int kBlur = 5;  // findTransformECC's gaussFiltSize: both images blurred 5x5 first

// ECC's correlation at the identity: zero-mean normalised cross-correlation of the blurred images.
double correlation(const cv::Mat1f& a, const cv::Mat1f& b) {
  cv::Mat1f ab, bb;
  cv::GaussianBlur(a, ab, cv::Size(kBlur, kBlur), 0, 0);
  cv::GaussianBlur(b, bb, cv::Size(kBlur, kBlur), 0, 0);
  ab -= cv::mean(ab)[0];
  bb -= cv::mean(bb)[0];
  const double norm = std::sqrt(ab.dot(ab) * bb.dot(bb));
  return norm > 0 ? ab.dot(bb) / norm : 0.0;
}

}  // namespace

PhotoAlignment align_render_to_photo(const cv::Mat1f& render, const cv::Mat1f& photo,
                                     double min_gain) {
  if (render.size() != photo.size())
    throw std::invalid_argument("photo alignment: the render and the photo differ in size");
  PhotoAlignment out;
  out.correlation_before = out.correlation_after = correlation(render, photo);
  cv::Mat1f warp = cv::Mat1f::eye(2, 3);
  try {
    // Finds the warp with render(x + shift) ~ photo(x).
    out.correlation_after = cv::findTransformECC(
        photo, render, warp, cv::MOTION_TRANSLATION,
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-5), cv::noArray(),
        kBlur);
  } catch (const cv::Exception&) {
    return out;  // no convergence (a flat or unrelated image): the masks stay where they are
  }
  out.shift_x = -warp(0, 2);
  out.shift_y = -warp(1, 2);
  out.applied = out.correlation_after - out.correlation_before >= min_gain;
  return out;
}

cv::Mat align_image(const cv::Mat& image, const PhotoAlignment& alignment) {
  if (!alignment.applied) return image.clone();
  const cv::Matx23f move(1, 0, float(alignment.shift_x), 0, 1, float(alignment.shift_y));
  cv::Mat out;
  cv::warpAffine(image, out, move, image.size(), cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0);
  return out;
}

}  // namespace gslift
