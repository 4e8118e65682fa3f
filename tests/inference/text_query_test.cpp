// Rendering selections through the render cache, checked against the rasterizer's own alpha, and
// the answers registered to a view's photo.
#include "nodes/inference/text_query.hpp"

#include <opencv2/imgproc.hpp>

#include "nodes/splat/rasterizer.hpp"
#include "nodes/text/hashing_text_encoder.hpp"
#include "runtime/node.hpp"
#include "tests/inference/query_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("a selection renders as the accumulated alpha of its Gaussians") {
  const GaussianModel model = test::two_blobs();
  const Camera cam = test::query_camera();
  const QueryView view(model, cam, Pose{});
  RenderSettings alpha_only;
  alpha_only.rgb = false;
  alpha_only.alpha = true;
  const RenderOutput full = render(model, cam, Pose{}, alpha_only);

  const cv::Mat1f all = view.render({1.f, 1.f});
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x)
      REQUIRE(all(y, x) == Approx(full.alpha[size_t(y) * cam.width + x]).margin(1e-6));

  // Left blob alone: its centre pixel is ~0.98 opaque, the right blob's centre is untouched.
  const cv::Mat1f left = view.render(selection_indicator(model.instance_ids, 2, {0}));
  CHECK(left(24, 17) > 0.9f);
  CHECK(left(24, 47) == 0.f);
  const cv::Mat1b mask = view.mask(selection_indicator(model.instance_ids, 2, {0}), 0.5f);
  CHECK(mask(24, 17) == 255);
  CHECK(mask(24, 47) == 0);
  CHECK(mask(24, 32) == 0);  // between the blobs
  // Relevancy blend: instance relevancies 0.25 and 0.75 weight the alpha.
  Eigen::VectorXf rel(2);
  rel << 0.25f, 0.75f;
  const cv::Mat1f blend = view.render(gaussian_values(model.instance_ids, rel));
  CHECK(blend(24, 17) == Approx(0.25f * all(24, 17)));
  CHECK(blend(24, 47) == Approx(0.75f * all(24, 47)));
  CHECK_THROWS_AS(view.render({1.f}), InputError);
}

TEST_CASE("instance planes render what the per-Gaussian product renders") {
  GaussianModel model = test::two_blobs();
  // A third Gaussian overlapping the left blob, unassigned: it must count in neither plane.
  model.resize(3);
  model.means = {-0.5f, 0.f, 2.f, 0.5f, 0.f, 2.f, -0.4f, 0.f, 1.8f};
  for (int a = 0; a < 3; ++a) model.log_scales[6 + a] = std::log(0.1f);
  model.opacity_logits = {4.f, 4.f, 1.f};
  model.instance_ids = {0, 1, -1};
  const Camera cam = test::query_camera();
  const QueryView view(model, cam, Pose{});
  Eigen::VectorXf rel(2);
  rel << 0.25f, 0.75f;
  const cv::Mat1f by_instance = view.render_instances(rel);
  const cv::Mat1f by_gaussian = view.render(gaussian_values(model.instance_ids, rel));
  const cv::Mat1f left_alpha = view.render(selection_indicator(model.instance_ids, 2, {0}));
  const cv::Mat1b left = view.instance_mask({0}, 0.5f);
  int in_left = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      REQUIRE(by_instance(y, x) == Approx(by_gaussian(y, x)).margin(1e-6));
      REQUIRE(left(y, x) == (left_alpha(y, x) >= 0.5f ? 255 : 0));
      in_left += left(y, x) != 0;
    }
  CHECK(in_left > 0);
  // The unassigned Gaussian in front hides part of the left blob: at its centre the left
  // instance alone has less alpha than at the blob's far edge without it.
  const Eigen::VectorXf left_only = Eigen::VectorXf::Unit(2, 0);
  CHECK(view.render_instances(left_only)(24, 17) < 0.9f);
  // Selecting nothing, or an id no Gaussian has, renders nothing.
  CHECK(cv::countNonZero(view.instance_mask({}, 0.5f)) == 0);
  CHECK(cv::countNonZero(view.instance_mask({5}, 0.5f)) == 0);
}

TEST_CASE("unassigned Gaussians and out-of-range ids") {
  Eigen::VectorXf v(2);
  v << 3.f, 5.f;
  CHECK(gaussian_values({1, -1, 0}, v) == std::vector<float>{5.f, 0.f, 3.f});
  CHECK(selection_indicator({1, -1, 0}, 2, {1}) == std::vector<float>{1.f, 0.f, 0.f});

  GaussianModel model = test::two_blobs();
  model.instance_ids = {0, 2};  // only two instances below
  InstanceSet instances;
  instances.prototypes = Eigen::MatrixXf::Zero(2, 1);
  const HashingTextEncoder enc(32);
  instances.semantics.resize(2, 32);
  instances.semantics.row(0) = enc.encode("patient").transpose();
  instances.semantics.row(1) = enc.encode("monitor").transpose();
  Capture capture;
  CHECK_THROWS_AS(answer_text_queries(model, instances, enc, capture, {}, {"patient"}, {}),
                  InputError);
  model.instance_ids = {0, 1};
  const HashingTextEncoder wider(64);
  CHECK_THROWS_AS(answer_text_queries(model, instances, wider, capture, {}, {"patient"}, {}),
                  InputError);
}

namespace {

// Two instances whose semantics are the embeddings of "patient" and "monitor".
InstanceSet patient_and_monitor(const TextEncoder& enc) {
  InstanceSet instances;
  instances.prototypes = Eigen::MatrixXf::Zero(2, 1);
  instances.semantics.resize(2, enc.dim());
  instances.semantics.row(0) = enc.encode("patient").transpose();
  instances.semantics.row(1) = enc.encode("monitor").transpose();
  return instances;
}

// The view "v" of the two-blob scene, at the origin.
View blob_view() {
  View view;
  view.name = "v";
  view.camera = test::query_camera();
  return view;
}

}  // namespace

TEST_CASE("normalised relevancy maps divide the blend by the accumulated alpha") {
  const GaussianModel model = test::two_blobs();
  const HashingTextEncoder enc(64);
  const InstanceSet instances = patient_and_monitor(enc);
  Capture capture;
  capture.views.push_back(blob_view());
  TextQueryOptions o;
  o.vocabulary = {"patient", "monitor"};  // monitor competes, so it does not answer "patient"
  const TextQueryResults sum =
      answer_text_queries(model, instances, enc, capture, {0}, {"patient"}, o);
  o.normalise_relevancy = true;
  const TextQueryResults mean =
      answer_text_queries(model, instances, enc, capture, {0}, {"patient"}, o);
  REQUIRE(sum.instances[0] == std::vector<int>{0});
  const float r0 = sum.relevancy[0][0];
  CHECK(r0 > 0.99f);
  // One Gaussian per pixel: the mean is the instance's relevancy, the sum is scaled by alpha.
  CHECK(mean.views[0].relevancy[0](24, 17) == Approx(r0));
  CHECK(mean.views[0].relevancy[0](20, 15) == Approx(r0));
  CHECK(sum.views[0].relevancy[0](20, 15) < 0.9f * r0);
  CHECK(sum.views[0].masks[0](24, 17) == 255);
}

TEST_CASE("selection: closed set takes the argmax query, relevancy every instance above the bar") {
  const HashingTextEncoder enc(64);
  const InstanceSet instances = patient_and_monitor(enc);
  TextQueryOptions o = text_query_param_table().read({{"selection", std::string("closed_set")}});
  o.vocabulary = {"patient", "monitor"};
  TextQueryResults r;
  r.queries = {"patient"};
  select_instances(instances, enc, o, r);
  CHECK(r.instances[0] == std::vector<int>{0});
  // Relevancy with a bar of 0: every instance with a relevancy (a softmax, > 0) is selected.
  o = text_query_param_table().read(
      {{"selection", std::string("relevancy")}, {"relevancy_threshold", 0.0}}, o);
  CHECK(o.selection == QuerySelection::Relevancy);
  select_instances(instances, enc, o, r);
  CHECK(r.instances[0] == std::vector<int>{0, 1});
  CHECK_THROWS_AS(text_query_param_table().read({{"selection", std::string("top_k")}}),
                  std::invalid_argument);
}

TEST_CASE("answers registered to a photo that sits 3 px right of the render move with it") {
  GaussianModel model = test::two_blobs();
  model.sh = {1.5f, 0.f, 0.f, 0.f, 1.5f, 0.f};  // a red and a green blob on black
  const HashingTextEncoder enc(64);
  const InstanceSet instances = patient_and_monitor(enc);
  Capture capture;
  View view = blob_view();
  // The photo: the model's render with its content moved 3 px to the right.
  const RenderOutput r = render(model, view.camera, Pose{}, RenderSettings{});
  cv::Mat3f rgb(r.height, r.width);
  std::copy(r.rgb.begin(), r.rgb.end(), reinterpret_cast<float*>(rgb.data));
  cv::Mat3b photo;
  rgb.convertTo(photo, CV_8U, 255);
  cv::warpAffine(photo, photo, cv::Matx23f(1, 0, 3, 0, 1, 0), photo.size());
  view.rgb = ImageSource::in_memory(photo);
  capture.views.push_back(view);
  TextQueryOptions o;
  o.vocabulary = {"patient", "monitor"};
  const TextQueryResults plain =
      answer_text_queries(model, instances, enc, capture, {0}, {"patient"}, o);
  o.align.to_photo = true;
  std::vector<PhotoAlignment> alignments;
  const TextQueryResults moved =
      answer_text_queries(model, instances, enc, capture, {0}, {"patient"}, o, &alignments);
  REQUIRE(alignments.size() == 1);
  REQUIRE(alignments[0].applied);
  CHECK(alignments[0].shift_x == Approx(3.0).margin(0.1));
  CHECK(std::abs(alignments[0].shift_y) < 0.1);
  // The mask and the relevancy map are the unaligned ones 3 columns to the right.
  const cv::Mat1b& a = plain.views[0].masks[0];
  const cv::Mat1b& b = moved.views[0].masks[0];
  REQUIRE(cv::countNonZero(a) > 0);
  CHECK(cv::countNonZero(a.colRange(0, 61) != b.colRange(3, 64)) == 0);
  CHECK(moved.views[0].relevancy[0](24, 20) == plain.views[0].relevancy[0](24, 17));
}
