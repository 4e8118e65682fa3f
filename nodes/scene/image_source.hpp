// An image that lives either in memory or in a file read on demand. Captures hold these instead of
// decoded pixels so that a node loads one view at a time: preloading every image and mask of a
// capture is the most common way the reference implementations run out of memory.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>

#include <opencv2/core.hpp>

namespace gslift {

class ImageSource {
 public:
  using Reader = std::function<cv::Mat(const std::filesystem::path&)>;

  ImageSource() = default;
  static ImageSource in_memory(cv::Mat image);
  static ImageSource on_disk(std::filesystem::path path, Reader reader);

  bool present() const { return !path_.empty() || !image_.empty(); }
  const std::filesystem::path& path() const { return path_; }
  // Decodes the file on every call (nothing is cached); throws InputError naming the file when it
  // cannot be read. Returns an empty Mat when the source is absent.
  cv::Mat load() const;

 private:
  std::filesystem::path path_;
  Reader reader_;
  cv::Mat image_;
};

}  // namespace gslift
