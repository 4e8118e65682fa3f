// The port types' binary forms (nodes/scene/port_archive.hpp): every field comes back bit for
// bit, and a damaged archive throws ArchiveError before allocating what it claims.
#include <limits>

#include <opencv2/imgproc.hpp>

#include "nodes/scene/port_archive.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

template <class T>
T round_trip(const T& value) {
  ByteWriter w;
  write(w, value);
  ByteReader r(w.bytes());
  T back;
  read(r, back);
  CHECK(r.done());
  // Writing what was read gives the same bytes: no field is lost on the way back.
  ByteWriter again;
  write(again, back);
  CHECK(again.bytes() == w.bytes());
  return back;
}

cv::Mat1b disc(int w, int h) {
  cv::Mat1b m(h, w, uchar(0));
  cv::circle(m, {w / 2, h / 3}, h / 4, cv::Scalar(255), -1);
  return m;
}

}  // namespace

TEST_CASE("boxes, masks and label maps come back field for field", "[port_archive]") {
  BoxSet boxes;
  boxes.views = {{"cam_00", 3, {{1.5f, 2.f, 30.25f, 40.f, "surgeon", 0.75f, 2, 3, 4}}},
                 {"cam_01", 0, {}}};
  const BoxSet b = round_trip(boxes);
  REQUIRE(b.views.size() == 2);
  CHECK(b.views[0].rounds == 3);
  CHECK(b.views[0].boxes[0].x2 == 30.25f);
  CHECK(b.views[0].boxes[0].label == "surgeon");
  CHECK(b.views[0].boxes[0].source_index == 4);

  MaskSet masks;
  masks.views = {{"cam_00", {{disc(33, 17), "table", 0.5f, 1, 2}}}};
  const MaskSet m = round_trip(masks);
  REQUIRE(m.views[0].masks.size() == 1);
  CHECK(cv::countNonZero(m.views[0].masks[0].pixels != masks.views[0].masks[0].pixels) == 0);
  CHECK(m.views[0].masks[0].pixels.size() == cv::Size(33, 17));
  CHECK(m.views[0].masks[0].granularity == 2);

  LabelMapSet labels;
  labels.labels = 7;
  cv::Mat1i ids(5, 4, 3);
  ids(2, 1) = -1;
  labels.views = {{"cam_00", ids}};
  const LabelMapSet l = round_trip(labels);
  CHECK(l.labels == 7);
  CHECK(l.views[0].labels(2, 1) == -1);
  CHECK(l.views[0].labels(4, 3) == 3);
}

TEST_CASE("a Gaussian model and feature outputs come back bit for bit", "[port_archive]") {
  GaussianModel g;
  g.sh_degree = 1;
  g.feature_dim = 2;
  g.resize(3);
  for (size_t i = 0; i < g.means.size(); ++i) g.means[i] = 0.1f * float(i) + 1e-7f;
  g.features = {1, 2, 3, 4, 5, std::numeric_limits<float>::denorm_min()};
  g.sh[5] = -0.25f;
  g.instance_ids = {0, -1, 4};
  const GaussianModel back = round_trip(g);
  CHECK(back.means == g.means);
  CHECK(back.features == g.features);
  CHECK(back.sh == g.sh);
  CHECK(back.instance_ids == g.instance_ids);
  CHECK(back.class_ids.empty());

  InstanceSet inst;
  inst.prototypes = Eigen::MatrixXf::Random(3, 4);
  inst.labels = {"a", "", "c"};
  inst.semantics = Eigen::MatrixXf::Random(3, 2);
  inst.mask_instance = {{0, -1}, {}};
  const InstanceSet i = round_trip(inst);
  CHECK(i.prototypes == inst.prototypes);
  CHECK(i.mask_instance == inst.mask_instance);

  LiftedInstances lifted;
  lifted.samples = {{0, 1, 2, 3}, {4, 5, 6, 7}};
  lifted.labels = {1, -1};
  lifted.prototypes = Eigen::MatrixXf::Random(2, 5);
  const LiftedInstances li = round_trip(lifted);
  CHECK(li.samples[1].y == 7);
  CHECK(li.prototypes == lifted.prototypes);

  ViewClassifiers vc;
  vc.dim = 2;
  vc.tau = 12.5;
  vc.views = {{"cam_00", 2, {1, 2, 3, 4}}};
  CHECK(round_trip(vc).views[0].weights == vc.views[0].weights);
  LabelClassifier lc{2, 1, {0.5f, 0.25f}, {0.125f}};
  CHECK(round_trip(lc).bias == lc.bias);
}

TEST_CASE("semantic maps, prompts, text answers and vocabularies come back", "[port_archive]") {
  SemanticMaps sem;
  sem.classes = {"background", "table"};
  SemanticView view =
      label_confidence_view("cam_00", cv::Mat1i(2, 3, 1), cv::Mat1f(2, 3, 0.75f), 2);
  sem.views = {view};
  const SemanticMaps s = round_trip(sem);
  CHECK(s.views[0].probabilities == view.probabilities);
  CHECK(s.views[0].confidence(1, 2) == 0.75f);

  PromptSet prompts;
  prompts.prompts = {{"lamp", PromptKind::Scribble, "cam_01", {{1, 2}, {3, 4}}, {{5, 6}}, {}},
                     {"bed", PromptKind::Mask, "cam_00", {}, {}, disc(8, 8)}};
  prompts.vote_balance = {{0.5f, -1.f, 0.f}, {}};
  const PromptSet p = round_trip(prompts);
  CHECK(p.vote_balance == prompts.vote_balance);
  CHECK(p.prompts[0].kind == PromptKind::Scribble);
  CHECK(p.prompts[0].positive[1] == cv::Point(3, 4));
  CHECK(p.prompts[1].mask.size() == cv::Size(8, 8));

  TextQueryResults answers;
  answers.queries = {"surgeon"};
  answers.instances = {{2, 5}};
  answers.relevancy = {Eigen::VectorXf::LinSpaced(4, 0, 1)};
  answers.views = {{"cam_04", {disc(6, 4)}, {cv::Mat1f(4, 6, 0.5f)}}};
  const TextQueryResults a = round_trip(answers);
  CHECK(a.relevancy[0] == answers.relevancy[0]);
  CHECK(a.views[0].relevancy[0](3, 5) == 0.5f);

  Vocabulary vocab;
  vocab.source = "vocab.yaml";
  vocab.entities = {{"surgeon", true, "at the table", "operates", "green gown"}};
  vocab.prompt = "find";
  const Vocabulary v = round_trip(vocab);
  CHECK(v.entities[0].person);
  CHECK(v.entities[0].appearance == "green gown");
}

TEST_CASE("view poses come back bit for bit, and a pose count that disagrees is refused",
          "[port_archive]") {
  ViewPoses poses;
  poses.views = {"cam_00", "cam_01"};
  Eigen::Matrix4d c2w = Eigen::Matrix4d::Identity();
  c2w.block<3, 3>(0, 0) << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  c2w.block<3, 1>(0, 3) << 0.1, -2.5, 1.0 / 3;
  poses.poses = {Pose(), Pose::from_camera_to_world(c2w)};
  const ViewPoses back = round_trip(poses);
  CHECK(back.views == poses.views);
  REQUIRE(back.poses.size() == 2);
  CHECK(back.poses[1].R == poses.poses[1].R);
  CHECK(back.poses[1].t == poses.poses[1].t);
  ViewPoses short_of_one = poses;
  short_of_one.views.push_back("cam_02");
  ByteWriter w;
  write(w, short_of_one);
  ByteReader r(w.bytes());
  ViewPoses refused;
  CHECK_THROWS_AS(read(r, refused), ArchiveError);
}

TEST_CASE("a damaged archive throws instead of allocating what it claims", "[port_archive]") {
  GaussianModel g;
  g.resize(100);
  ByteWriter w;
  write(w, g);
  const std::string bytes = w.bytes();
  // Every truncation is an error, never a crash or a smaller model.
  for (size_t cut : {size_t(0), size_t(3), bytes.size() / 2, bytes.size() - 1}) {
    ByteReader r(std::string_view(bytes).substr(0, cut));
    GaussianModel back;
    CHECK_THROWS_AS(read(r, back), ArchiveError);
  }
  // A count of 2^60 floats in a 20-byte archive.
  ByteWriter huge;
  huge.put<int32_t>(0);
  huge.put<int32_t>(0);
  huge.put<uint64_t>(uint64_t(1) << 60);
  ByteReader r(huge.bytes());
  GaussianModel back;
  CHECK_THROWS_AS(read(r, back), ArchiveError);
  // Arrays whose sizes disagree with each other.
  GaussianModel odd = g;
  odd.quats.pop_back();
  ByteWriter ow;
  write(ow, odd);
  ByteReader orr(ow.bytes());
  CHECK_THROWS_AS(read(orr, back), ArchiveError);
}
