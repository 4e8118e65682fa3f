#include "nodes/scene/semantic_maps.hpp"

#include <algorithm>
#include <cctype>

#include "base/errors.hpp"

namespace gslift {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace

std::vector<std::string> semantic_classes(const Capture& capture) {
  if (capture.classes.empty())
    throw InputError("capture '" + capture.name +
                     "' has no class vocabulary (gt/classes.yaml): semantic fusion and its "
                     "evaluation need the class ids");
  const int last = capture.classes.rbegin()->first;
  std::vector<std::string> names(static_cast<size_t>(last) + 1);
  for (int id = 0; id <= last; ++id) {
    auto it = capture.classes.find(id);
    if (it != capture.classes.end())
      names[id] = it->second;
    else if (id == 0)
      names[id] = "background";
    else
      throw InputError("capture '" + capture.name + "': class id " + std::to_string(id) +
                       " is missing from its vocabulary (ids must be 1..N)");
  }
  return names;
}

std::vector<std::string> semantic_classes(const Capture& capture,
                                          const std::vector<std::string>& given) {
  if (given.empty()) return semantic_classes(capture);
  std::vector<std::string> names{"background"};
  names.insert(names.end(), given.begin(), given.end());
  return names;
}

int class_index(const std::vector<std::string>& classes, const std::string& label) {
  const std::string l = lower(label);
  for (size_t i = 0; i < classes.size(); ++i)
    if (lower(classes[i]) == l) return static_cast<int>(i);
  return -1;
}

SemanticView label_confidence_view(const std::string& name, const cv::Mat1i& labels,
                                   const cv::Mat1f& confidence, int classes) {
  SemanticView v;
  v.view = name;
  v.labels = labels.clone();
  v.confidence = confidence.clone();
  const int n = labels.rows * labels.cols;
  v.probabilities.assign(size_t(n) * classes, 1.f / classes);
  for (int p = 0; p < n; ++p) {
    const int l = labels(p / labels.cols, p % labels.cols);
    if (l < 0) {
      v.confidence(p / labels.cols, p % labels.cols) = 1.f / classes;
      continue;
    }
    if (l >= classes)
      throw InputError("semantic view '" + name + "': label " + std::to_string(l) + " of " +
                       std::to_string(classes) + " classes");
    const float s = confidence(p / labels.cols, p % labels.cols);
    float* d = v.pixel(p, classes);
    std::fill(d, d + classes, classes > 1 ? (1.f - s) / (classes - 1) : 1.f);
    d[l] = s;
  }
  return v;
}

void set_argmax(SemanticView& v, int classes, int width, int height) {
  v.labels.create(height, width);
  v.confidence.create(height, width);
  for (int p = 0; p < width * height; ++p) {
    const float* d = v.pixel(p, classes);
    const int best = static_cast<int>(std::max_element(d, d + classes) - d);
    v.labels(p / width, p % width) = best;
    v.confidence(p / width, p % width) = d[best];
  }
}

}  // namespace gslift
