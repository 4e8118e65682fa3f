#include "nodes/scene/image_source.hpp"

namespace gslift {

ImageSource ImageSource::in_memory(cv::Mat image) {
  ImageSource s;
  s.image_ = std::move(image);
  return s;
}

ImageSource ImageSource::on_disk(std::filesystem::path path, Reader reader) {
  ImageSource s;
  s.path_ = std::move(path);
  s.reader_ = std::move(reader);
  return s;
}

cv::Mat ImageSource::load() const {
  if (!image_.empty()) return image_;
  if (path_.empty()) return {};
  return reader_(path_);
}

}  // namespace gslift
