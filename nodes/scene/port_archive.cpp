#include "nodes/scene/port_archive.hpp"

#include <limits>

namespace gslift {

namespace {

// Sizes from the archive are checked before anything is allocated with them.
int read_int(ByteReader& r, int min, int max, const char* what) {
  const int32_t v = r.get<int32_t>();
  if (v < min || v > max)
    throw ArchiveError(std::string(what) + " " + std::to_string(v) + " out of range");
  return v;
}

template <class T>
void read_typed_mat(ByteReader& r, cv::Mat_<T>& out) {
  cv::Mat m;
  read(r, m);
  if (!m.empty() && m.type() != cv::traits::Type<T>::value)
    throw ArchiveError("archived image has OpenCV type " + std::to_string(m.type()) +
                       ", expected " + std::to_string(cv::traits::Type<T>::value));
  out = m;
}

template <class T, class F>
void write_list(ByteWriter& w, const std::vector<T>& items, F write_item) {
  w.put<uint64_t>(items.size());
  for (const auto& item : items) write_item(item);
}

// Each item takes at least `min_bytes` in the archive: a damaged count fails before reserve().
template <class T, class F>
void read_list(ByteReader& r, std::vector<T>& items, size_t min_bytes, F read_item) {
  const uint64_t n = r.count(min_bytes);
  items.clear();
  items.reserve(n);
  for (uint64_t i = 0; i < n; ++i) {
    items.emplace_back();
    read_item(items.back());
  }
}

void write(ByteWriter& w, const Eigen::VectorXf& v) {
  w.put_array(v.data(), size_t(v.size()));
}
void read(ByteReader& r, Eigen::VectorXf& v) {
  const auto values = r.get_vector<float>();
  v = Eigen::Map<const Eigen::VectorXf>(values.data(), Eigen::Index(values.size()));
}

void write_ints(ByteWriter& w, const std::vector<int>& v) {
  w.put_array(v.data(), v.size());
}
std::vector<int> read_ints(ByteReader& r) {
  return r.get_vector<int>();
}

}  // namespace

void write(ByteWriter& w, const cv::Mat& m) {
  w.put<int32_t>(m.type());
  w.put<int32_t>(m.rows);
  w.put<int32_t>(m.cols);
  const cv::Mat dense = m.isContinuous() ? m : m.clone();
  w.put_array(dense.data, dense.total() * dense.elemSize());
}

void read(ByteReader& r, cv::Mat& m) {
  const int type = r.get<int32_t>();
  const int rows = read_int(r, 0, std::numeric_limits<int32_t>::max(), "image rows");
  const int cols = read_int(r, 0, std::numeric_limits<int32_t>::max(), "image cols");
  if (CV_MAT_DEPTH(type) > CV_16F || CV_MAT_CN(type) > 4)
    throw ArchiveError("archived image has an unknown OpenCV type " + std::to_string(type));
  const size_t elem = CV_ELEM_SIZE(type);
  const uint64_t bytes = r.count(1);
  if (bytes != uint64_t(rows) * uint64_t(cols) * elem)
    throw ArchiveError("archived image of " + std::to_string(rows) + " x " + std::to_string(cols) +
                       " holds " + std::to_string(bytes) + " bytes");
  m.create(rows, cols, type);
  r.get_raw(m.data, bytes);
}

void write(ByteWriter& w, const Eigen::MatrixXf& m) {
  w.put<int64_t>(m.rows());
  w.put<int64_t>(m.cols());
  w.put_array(m.data(), size_t(m.size()));
}

void read(ByteReader& r, Eigen::MatrixXf& m) {
  const int64_t rows = r.get<int64_t>();
  const int64_t cols = r.get<int64_t>();
  const auto values = r.get_vector<float>();
  if (rows < 0 || cols < 0 || uint64_t(rows) * uint64_t(cols) != values.size())
    throw ArchiveError("archived matrix of " + std::to_string(rows) + " x " + std::to_string(cols) +
                       " holds " + std::to_string(values.size()) + " values");
  m = Eigen::Map<const Eigen::MatrixXf>(values.data(), rows, cols);
}

void write(ByteWriter& w, const BoxSet& v) {
  write_list(w, v.views, [&](const ViewBoxes& view) {
    w.put_string(view.view);
    w.put<int32_t>(view.rounds);
    write_list(w, view.boxes, [&](const Box& b) {
      for (float x : {b.x1, b.y1, b.x2, b.y2, b.score}) w.put(x);
      w.put_string(b.label);
      for (int32_t x : {b.round, b.support, b.source_index}) w.put(x);
    });
  });
}

void read(ByteReader& r, BoxSet& v) {
  read_list(r, v.views, 12, [&](ViewBoxes& view) {
    view.view = r.get_string();
    view.rounds = r.get<int32_t>();
    read_list(r, view.boxes, 40, [&](Box& b) {
      for (float* x : {&b.x1, &b.y1, &b.x2, &b.y2, &b.score}) *x = r.get<float>();
      b.label = r.get_string();
      for (int* x : {&b.round, &b.support, &b.source_index}) *x = r.get<int32_t>();
    });
  });
}

void write(ByteWriter& w, const GaussianModel& v) {
  w.put<int32_t>(v.sh_degree);
  w.put<int32_t>(v.feature_dim);
  for (const auto* a : {&v.means, &v.log_scales, &v.quats, &v.opacity_logits, &v.sh, &v.features})
    w.put_vector(*a);
  w.put_vector(v.instance_ids);
  w.put_vector(v.class_ids);
}

void read(ByteReader& r, GaussianModel& v) {
  v.sh_degree = read_int(r, 0, 3, "SH degree");
  v.feature_dim = read_int(r, 0, std::numeric_limits<int32_t>::max(), "feature width");
  for (auto* a : {&v.means, &v.log_scales, &v.quats, &v.opacity_logits, &v.sh, &v.features})
    *a = r.get_vector<float>();
  v.instance_ids = r.get_vector<int32_t>();
  v.class_ids = r.get_vector<int32_t>();
  const size_t n = v.size();
  const size_t k = size_t(GaussianModel::sh_coeffs(v.sh_degree));
  const bool consistent = v.means.size() == 3 * n && v.log_scales.size() == 3 * n &&
                          v.quats.size() == 4 * n && v.sh.size() == 3 * k * n &&
                          v.features.size() == size_t(v.feature_dim) * n &&
                          (v.instance_ids.empty() || v.instance_ids.size() == n) &&
                          (v.class_ids.empty() || v.class_ids.size() == n);
  if (!consistent) throw ArchiveError("archived Gaussian model has inconsistent array sizes");
}

void write(ByteWriter& w, const InstanceSet& v) {
  write(w, v.prototypes);
  w.put_strings(v.labels);
  write(w, v.semantics);
  write_list(w, v.mask_instance, [&](const std::vector<int>& m) { write_ints(w, m); });
}

void read(ByteReader& r, InstanceSet& v) {
  read(r, v.prototypes);
  v.labels = r.get_strings();
  read(r, v.semantics);
  read_list(r, v.mask_instance, 8, [&](std::vector<int>& m) { m = read_ints(r); });
}

void write(ByteWriter& w, const LabelMapSet& v) {
  write_list(w, v.views, [&](const LabelMap& m) {
    w.put_string(m.view);
    write(w, m.labels);
  });
  w.put<int32_t>(v.labels);
}

void read(ByteReader& r, LabelMapSet& v) {
  read_list(r, v.views, 20, [&](LabelMap& m) {
    m.view = r.get_string();
    read_typed_mat(r, m.labels);
  });
  v.labels = r.get<int32_t>();
}

void write(ByteWriter& w, const ViewClassifiers& v) {
  w.put<int32_t>(v.dim);
  w.put<double>(v.tau);
  write_list(w, v.views, [&](const ViewClassifier& c) {
    w.put_string(c.view);
    w.put<int32_t>(c.classes);
    w.put_vector(c.weights);
  });
}

void read(ByteReader& r, ViewClassifiers& v) {
  v.dim = r.get<int32_t>();
  v.tau = r.get<double>();
  read_list(r, v.views, 20, [&](ViewClassifier& c) {
    c.view = r.get_string();
    c.classes = r.get<int32_t>();
    c.weights = r.get_vector<float>();
  });
}

void write(ByteWriter& w, const LabelClassifier& v) {
  w.put<int32_t>(v.dim);
  w.put<int32_t>(v.classes);
  w.put_vector(v.weights);
  w.put_vector(v.bias);
}

void read(ByteReader& r, LabelClassifier& v) {
  v.dim = r.get<int32_t>();
  v.classes = r.get<int32_t>();
  v.weights = r.get_vector<float>();
  v.bias = r.get_vector<float>();
}

void write(ByteWriter& w, const LiftedInstances& v) {
  static_assert(sizeof(SampledPixel) == 4 * sizeof(int), "SampledPixel is four ints");
  w.put_array(reinterpret_cast<const int*>(v.samples.data()), 4 * v.samples.size());
  write_ints(w, v.labels);
  write(w, v.prototypes);
}

void read(ByteReader& r, LiftedInstances& v) {
  const auto ints = read_ints(r);
  if (ints.size() % 4) throw ArchiveError("archived pixel samples are not four ints each");
  v.samples.resize(ints.size() / 4);
  for (size_t i = 0; i < v.samples.size(); ++i)
    v.samples[i] = {ints[4 * i], ints[4 * i + 1], ints[4 * i + 2], ints[4 * i + 3]};
  v.labels = read_ints(r);
  read(r, v.prototypes);
}

void write(ByteWriter& w, const MaskSet& v) {
  write_list(w, v.views, [&](const ViewMasks& view) {
    w.put_string(view.view);
    write_list(w, view.masks, [&](const Mask& m) {
      write(w, m.pixels);
      w.put_string(m.label);
      w.put<float>(m.score);
      w.put<int32_t>(m.box_index);
      w.put<int32_t>(m.granularity);
    });
  });
}

void read(ByteReader& r, MaskSet& v) {
  read_list(r, v.views, 16, [&](ViewMasks& view) {
    view.view = r.get_string();
    read_list(r, view.masks, 40, [&](Mask& m) {
      read_typed_mat(r, m.pixels);
      m.label = r.get_string();
      m.score = r.get<float>();
      m.box_index = r.get<int32_t>();
      m.granularity = r.get<int32_t>();
    });
  });
}

namespace {
void write_points(ByteWriter& w, const std::vector<cv::Point>& points) {
  write_list(w, points, [&](const cv::Point& p) {
    w.put<int32_t>(p.x);
    w.put<int32_t>(p.y);
  });
}
void read_points(ByteReader& r, std::vector<cv::Point>& points) {
  read_list(r, points, 8, [&](cv::Point& p) {
    p.x = r.get<int32_t>();
    p.y = r.get<int32_t>();
  });
}
}  // namespace

void write(ByteWriter& w, const PromptSet& v) {
  write_list(w, v.prompts, [&](const Prompt& p) {
    w.put_string(p.name);
    w.put<int32_t>(static_cast<int32_t>(p.kind));
    w.put_string(p.view);
    write_points(w, p.positive);
    write_points(w, p.negative);
    write(w, p.mask);
  });
  write_list(w, v.vote_balance,
             [&](const std::vector<float>& b) { w.put_array(b.data(), b.size()); });
}

void read(ByteReader& r, PromptSet& v) {
  read_list(r, v.prompts, 60, [&](Prompt& p) {
    p.name = r.get_string();
    p.kind = static_cast<PromptKind>(read_int(r, 0, int(PromptKind::Sam), "prompt kind"));
    p.view = r.get_string();
    read_points(r, p.positive);
    read_points(r, p.negative);
    read_typed_mat(r, p.mask);
  });
  read_list(r, v.vote_balance, 8, [&](std::vector<float>& b) { b = r.get_vector<float>(); });
}

void write(ByteWriter& w, const ViewPoses& v) {
  w.put_strings(v.views);
  write_list(w, v.poses, [&](const Pose& p) {
    w.put_array(p.R.data(), 9);
    w.put_array(p.t.data(), 3);
  });
}

void read(ByteReader& r, ViewPoses& v) {
  v.views = r.get_strings();
  read_list(r, v.poses, 2 * (8 + 8 * 3), [&](Pose& p) {
    r.get_array(p.R.data(), 9);
    r.get_array(p.t.data(), 3);
  });
  if (v.poses.size() != v.views.size())
    throw ArchiveError("archived poses: " + std::to_string(v.poses.size()) + " for " +
                       std::to_string(v.views.size()) + " views");
}

void write(ByteWriter& w, const SemanticMaps& v) {
  w.put_strings(v.classes);
  write_list(w, v.views, [&](const SemanticView& s) {
    w.put_string(s.view);
    w.put_vector(s.probabilities);
    write(w, s.labels);
    write(w, s.confidence);
  });
}

void read(ByteReader& r, SemanticMaps& v) {
  v.classes = r.get_strings();
  read_list(r, v.views, 40, [&](SemanticView& s) {
    s.view = r.get_string();
    s.probabilities = r.get_vector<float>();
    read_typed_mat(r, s.labels);
    read_typed_mat(r, s.confidence);
  });
}

void write(ByteWriter& w, const TextQueryResults& v) {
  w.put_strings(v.queries);
  write_list(w, v.instances, [&](const std::vector<int>& i) { write_ints(w, i); });
  write_list(w, v.relevancy, [&](const Eigen::VectorXf& x) { write(w, x); });
  write_list(w, v.views, [&](const TextQueryResults::ViewAnswers& a) {
    w.put_string(a.view);
    write_list(w, a.masks, [&](const cv::Mat1b& m) { write(w, m); });
    write_list(w, a.relevancy, [&](const cv::Mat1f& m) { write(w, m); });
  });
}

void read(ByteReader& r, TextQueryResults& v) {
  v.queries = r.get_strings();
  read_list(r, v.instances, 8, [&](std::vector<int>& i) { i = read_ints(r); });
  read_list(r, v.relevancy, 8, [&](Eigen::VectorXf& x) { read(r, x); });
  read_list(r, v.views, 24, [&](TextQueryResults::ViewAnswers& a) {
    a.view = r.get_string();
    read_list(r, a.masks, 20, [&](cv::Mat1b& m) { read_typed_mat(r, m); });
    read_list(r, a.relevancy, 20, [&](cv::Mat1f& m) { read_typed_mat(r, m); });
  });
}

void write(ByteWriter& w, const Vocabulary& v) {
  w.put_string(v.source);
  write_list(w, v.entities, [&](const EntityContext& e) {
    w.put_string(e.name);
    w.put<uint8_t>(e.person);
    for (const auto* s : {&e.spatial, &e.behaviour, &e.appearance}) w.put_string(*s);
  });
  w.put_string(v.prompt);
}

void read(ByteReader& r, Vocabulary& v) {
  v.source = r.get_string();
  read_list(r, v.entities, 33, [&](EntityContext& e) {
    e.name = r.get_string();
    e.person = r.get<uint8_t>() != 0;
    for (auto* s : {&e.spatial, &e.behaviour, &e.appearance}) *s = r.get_string();
  });
  v.prompt = r.get_string();
}

}  // namespace gslift
