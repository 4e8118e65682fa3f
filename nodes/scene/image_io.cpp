#include "nodes/scene/image_io.hpp"

#include <cmath>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "base/atomic_file.hpp"
#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "nodes/scene/camera.hpp"
#include "nodes/scene/image_header.hpp"

namespace gslift {

cv::Mat read_image(const std::filesystem::path& path, int flags) {
  require_regular_file(path, "image");
  // Only files that start like a format gslift reads reach OpenCV, whose sniffing would otherwise
  // hand them to decoders that are not safe on hostile bytes: a ".png" with "DICM" at offset 128
  // went to GDCM, whose assertion aborted the process (tests/data/fuzz_regressions/mask_png).
  // The size its header declares is checked before OpenCV allocates for it.
  const ImageHeader header = read_image_header(path);
  check_image_header(header, path.string() + " (" + header.format + " header)");
  cv::Mat m;
  try {
    m = cv::imread(path.string(), flags);
  } catch (const cv::Exception& e) {  // e.g. a header over OpenCV's own size limit
    throw InputError(path.string() + ": not a readable image (" + e.err + ")");
  }
  if (m.empty()) throw InputError(path.string() + ": not a readable image");
  check_image_size(m.cols, m.rows, path.string());
  return m;
}

namespace {

std::string describe(const cv::Mat& m) {
  return std::to_string(m.channels()) + "-channel " +
         std::to_string(8 * static_cast<int>(m.elemSize1())) + "-bit" +
         (m.depth() == CV_32F || m.depth() == CV_64F ? " float" : "");
}

// Encoded in memory, then written by write_file_atomically, which checks that every byte reached
// the file: cv::imwrite reported success on a full disk and left empty or truncated PNGs that
// were renamed into place (issue 16).
void write_image(const std::filesystem::path& path, const cv::Mat& m,
                 const std::vector<int>& flags = {}) {
  std::vector<uchar> bytes;
  if (!cv::imencode(path.extension().string(), m, bytes, flags))
    throw std::runtime_error(path.string() + ": cannot encode image");
  write_file_atomically(
      path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

void require_type(const std::filesystem::path& path, const cv::Mat& m, int type, const char* what) {
  if (m.empty() || m.type() != type)
    throw std::invalid_argument(path.string() + ": writer expects " + what);
}

// Float TIFFs are written uncompressed: OpenCV 4.6's LZW path with its float predictor does not
// round-trip float32 values exactly.
void write_float_image(const std::filesystem::path& path, const cv::Mat& m) {
  // OpenCV swaps channels 0 and 2 on write (it assumes BGR); pre-swap so the file holds the
  // channels in memory order (x, y, z for normals), as other TIFF readers will see them.
  cv::Mat file_order;
  if (m.channels() == 3)
    cv::cvtColor(m, file_order, cv::COLOR_RGB2BGR);
  else
    file_order = m;
  write_image(path, file_order, {cv::IMWRITE_TIFF_COMPRESSION, 1});
}

}  // namespace

cv::Mat read_rgb(const std::filesystem::path& path, const cv::Scalar& background) {
  cv::Mat m = read_image(path);
  if (m.depth() == CV_16U) m.convertTo(m, CV_8U, 1.0 / 257.0);
  if (m.depth() != CV_8U)
    throw InputError(path.string() + ": expected an 8- or 16-bit RGB image, got " + describe(m));
  cv::Mat rgb;
  switch (m.channels()) {
    case 1:
      cv::cvtColor(m, rgb, cv::COLOR_GRAY2RGB);
      break;
    case 3:
      cv::cvtColor(m, rgb, cv::COLOR_BGR2RGB);
      break;
    case 4: {
      // Straight (non-premultiplied) alpha, as PNG stores it: c = a * c + (1 - a) * background.
      rgb.create(m.size(), CV_8UC3);
      m.forEach<cv::Vec4b>([&](const cv::Vec4b& p, const int* pos) {
        const float a = p[3] / 255.f;
        cv::Vec3b& out = rgb.at<cv::Vec3b>(pos[0], pos[1]);
        for (int c = 0; c < 3; ++c)  // file order is BGRA, output RGB
          out[c] = cv::saturate_cast<uchar>(a * p[2 - c] + (1.f - a) * background[c]);
      });
      break;
    }
    default:
      throw InputError(path.string() + ": unsupported " + describe(m) + " image");
  }
  return rgb;
}

cv::Mat read_alpha(const std::filesystem::path& path) {
  cv::Mat m = read_image(path);
  if (m.channels() != 4) return {};
  cv::Mat alpha;
  cv::extractChannel(m, alpha, 3);
  if (alpha.depth() == CV_16U) alpha.convertTo(alpha, CV_8U, 1.0 / 257.0);
  return alpha;
}

cv::Mat read_depth(const std::filesystem::path& path, double scale) {
  cv::Mat m = read_image(path);
  if (m.channels() != 1)
    throw InputError(path.string() + ": depth must be single-channel, got " + describe(m));
  cv::Mat depth;
  if (m.depth() == CV_16U) {
    if (!(scale > 0)) throw InputError(path.string() + ": depth scale must be positive");
    m.convertTo(depth, CV_32F, 1.0 / scale);
    return depth;
  }
  if (m.depth() != CV_32F && m.depth() != CV_64F)
    throw InputError(path.string() + ": depth must be 16-bit or float32, got " + describe(m) +
                     " (8-bit depth cannot hold metric values)");
  m.convertTo(depth, CV_32F);
  depth.forEach<float>([](float& d, const int*) {
    if (!std::isfinite(d) || d < 0) d = 0.f;
  });
  return depth;
}

cv::Mat read_label_map(const std::filesystem::path& path, bool accept_8bit) {
  cv::Mat m = read_image(path);
  if (m.channels() != 1)
    throw InputError(path.string() + ": label map must be single-channel, got a " + describe(m) +
                     " colour image");
  if (m.depth() == CV_8U && !accept_8bit)
    throw InputError(path.string() +
                     ": 8-bit label map; the capture layout requires 16-bit ids "
                     "(8 bits wrap past 255)");
  if (m.depth() == CV_8U)
    spdlog::warn("{}: 8-bit label map; ids above 255 cannot be represented", path.string());
  else if (m.depth() != CV_16U && m.depth() != CV_32S)
    throw InputError(path.string() + ": label map must hold integers, got " + describe(m));
  cv::Mat labels;
  m.convertTo(labels, CV_32S);
  return labels;
}

cv::Mat read_float_tiff(const std::filesystem::path& path) {
  cv::Mat m = read_image(path);
  if (m.depth() != CV_32F)
    throw InputError(path.string() + ": expected a float32 map, got " + describe(m));
  if (m.channels() == 3) cv::cvtColor(m, m, cv::COLOR_BGR2RGB);  // back to file order
  return m;
}

void write_rgb_png(const std::filesystem::path& path, const cv::Mat& rgb) {
  require_type(path, rgb, CV_8UC3, "CV_8UC3 RGB");
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  write_image(path, bgr);
}

void write_depth_png_mm(const std::filesystem::path& path, const cv::Mat& depth) {
  require_type(path, depth, CV_32FC1, "CV_32FC1 metres");
  cv::Mat1w mm(depth.size());
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x) {
      const double v = std::round(depth.at<float>(y, x) * 1000.0);
      mm(y, x) = (std::isfinite(v) && v > 0 && v <= 65535) ? static_cast<uint16_t>(v) : 0;
    }
  write_image(path, mm);
}

void write_depth_tiff(const std::filesystem::path& path, const cv::Mat& depth) {
  require_type(path, depth, CV_32FC1, "CV_32FC1 metres");
  write_float_image(path, depth);
}

void write_label_png16(const std::filesystem::path& path, const cv::Mat& labels) {
  require_type(path, labels, CV_32SC1, "CV_32SC1 ids");
  double lo = 0, hi = 0;
  cv::minMaxLoc(labels, &lo, &hi);
  if (lo < 0 || hi > 65535)
    throw InputError(path.string() + ": label ids must be in [0, 65535] for a 16-bit PNG, got [" +
                     std::to_string(static_cast<long>(lo)) + ", " +
                     std::to_string(static_cast<long>(hi)) + "]");
  cv::Mat out;
  labels.convertTo(out, CV_16U);
  write_image(path, out);
}

void write_float_tiff(const std::filesystem::path& path, const cv::Mat& map) {
  if (map.empty() || (map.type() != CV_32FC1 && map.type() != CV_32FC3))
    throw std::invalid_argument(path.string() + ": writer expects CV_32FC1 or CV_32FC3");
  write_float_image(path, map);
}

}  // namespace gslift
