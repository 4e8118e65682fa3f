// Proto-SaGa's view classifiers trained jointly with the reconstruction (Eq. 8) and Gaga's 3D KL
// neighbour regulariser (neighbour_kl.hpp): a hand-computed KL case, finite differences, the
// nearest-centre search, and a tiny joint run.
#include <cmath>
#include <random>

#include "nodes/features/label_classifier.hpp"
#include "nodes/features/neighbour_kl.hpp"
#include "nodes/features/view_classifiers.hpp"
#include "tests/splat/train_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("neighbour KL: a hand-computed pair") {
  // 2 classes, W = I, b = 0: f0 = (0, 0) gives p = (1/2, 1/2); f1 = (ln 3, 0) gives q = (3/4, 1/4).
  const std::vector<float> features = {0.f, 0.f, float(std::log(3.0)), 0.f};
  const std::vector<float> W = {1, 0, 0, 1}, b = {0, 0};
  std::vector<float> gf(4, 0.f), gw(4, 0.f), gb(2, 0.f);
  // Sample 0, neighbours {0 (itself), 1}: KL(p||p) = 0, KL(p||q) = 1/2 ln(4/3); lambda 2, C = 2:
  // L = 2 / 2 * (0 + 1/2 ln(4/3)) / 2.
  const double L = neighbour_kl_loss(features.data(), 2, W.data(), b.data(), 2, {0}, {0, 1}, 2, 2.0,
                                     gf.data(), gw.data(), gb.data());
  CHECK(L == Approx(0.25 * std::log(4.0 / 3.0)).epsilon(1e-6));  // f1 is ln 3 in float
  // Gaussian 1 is only a neighbour: dL/dq_c = -s p_c / q_c with s = lambda / (C S k) = 1/2, and
  // through the softmax dz_c = q_c (g_c - sum_d q_d g_d) = s (q_c - p_c) = (1/8, -1/8), its
  // feature gradient (W = I).
  CHECK(gf[2] == Approx(0.125).epsilon(1e-6));
  CHECK(gf[3] == Approx(-0.125).epsilon(1e-6));
}

TEST_CASE("neighbour KL: gradients match central differences") {
  std::mt19937 rng(3);
  std::normal_distribution<float> g(0.f, 1.f);
  const int n = 7, dim = 3, classes = 4, k = 3;
  std::vector<float> f(n * dim), W(classes * dim), b(classes);
  for (float& v : f) v = g(rng);
  for (float& v : W) v = g(rng);
  for (float& v : b) v = 0.5f * g(rng);
  const std::vector<int> samples = {0, 3, 5};
  const std::vector<int> neighbours = {0, 1, 2, 3, 5, 6, 5, 0, 4};
  auto loss = [&](float* gf, float* gw, float* gb) {
    return neighbour_kl_loss(f.data(), dim, W.data(), b.data(), classes, samples, neighbours, k,
                             2.0, gf, gw, gb);
  };
  std::vector<float> gf(f.size(), 0.f), gw(W.size(), 0.f), gb(b.size(), 0.f);
  loss(gf.data(), gw.data(), gb.data());
  std::vector<float> sf(f.size()), sw(W.size()), sb(b.size());
  for (auto [param, grad] : {std::pair{&f, &gf}, std::pair{&W, &gw}, std::pair{&b, &gb}}) {
    for (size_t i = 0; i < param->size(); ++i) {
      const float x = (*param)[i];
      (*param)[i] = x + 1e-2f;
      const double hi = loss(sf.data(), sw.data(), sb.data());
      (*param)[i] = x - 1e-2f;
      const double lo = loss(sf.data(), sw.data(), sb.data());
      (*param)[i] = x;
      CHECK((*grad)[i] == Approx((hi - lo) / 2e-2).margin(2e-4).epsilon(2e-3));
    }
  }
}

TEST_CASE("neighbour KL: nearest centres, the query first") {
  // Centres on the x axis at 0, 1, 3, 7, 12: from 3 the nearest are 3 (itself), 1 (2 away), 0.
  const std::vector<float> means = {0, 0, 0, 1, 0, 0, 3, 0, 0, 7, 0, 0, 12, 0, 0};
  const GaussianNeighbours tree(means);
  CHECK(tree.nearest({2, 4}, 3) == std::vector<int>{2, 1, 0, 4, 3, 2});
}

TEST_CASE("view classifiers trained jointly with the reconstruction") {
  const Capture capture = test::rendered_capture();
  // Two "SAM masks" per view: the left and right halves of the image, class 0 the bottom rows.
  LabelMapSet partitions;
  for (const View& v : capture.views) {
    cv::Mat1i m(v.camera.height, v.camera.width, 0);
    m(cv::Rect(0, 0, m.cols / 2, m.rows - 8)) = 1;
    m(cv::Rect(m.cols / 2, 0, m.cols - m.cols / 2, m.rows - 8)) = 2;
    partitions.views.push_back({v.name, m});
  }
  partitions.labels = 2;
  ViewClassifierOptions o;
  o.training = FeatureTraining::Joint;
  o.dim = 4;
  o.pixels_per_view = 256;
  o.lr = 1e-2;
  o.classifier_lr = 1e-2;
  o.recon.iterations = 120;
  o.recon.init.pixel_stride = 1;
  o.recon.init.footprint_factor = 2;
  o.seed = 2;
  const ViewClassifierResult r = train_view_classifiers_jointly(capture, partitions, o);
  REQUIRE(r.recon);
  CHECK(r.recon->iterations_run == 120);
  CHECK(r.model.feature_dim == 4);
  CHECK(r.model.features.size() == r.model.size() * 4);
  CHECK(r.classifiers.views.size() == 4);  // the held-out view's map is not trained on
  CHECK(r.classifiers.views[0].classes == 3);
  INFO("cross-entropy " << r.loss_start << " -> " << r.loss_end);
  CHECK(r.loss_end < 0.5 * r.loss_start);
  CHECK(r.loss_end < 0.5 * std::log(3.0));  // below half the cross-entropy of a uniform guess
  CHECK(r.recon->train_psnr > 25);
}

TEST_CASE("joint training's recon_recipe sets the fields splat.reconstruct's recipe sets") {
  // The graph applies a preset by setting its params by name: each recon_<name> the preset names
  // must be a param of the node and land on the field the recipe sets in splat.reconstruct.
  const auto presets = recipe_presets("recon_");
  REQUIRE(presets.count("depth_prior") == 1);
  REQUIRE(presets.count("none") == 0);  // none sets nothing: no preset
  ViewClassifierOptions joint;
  for (const auto& [name, value] : presets.at("depth_prior")) {
    INFO(name);
    CHECK(name.rfind("recon_", 0) == 0);
    CHECK(view_classifier_param_table().set(joint, name, value));
  }
  ReconstructOptions expected;
  apply_recipe(expected, Recipe::DepthPrior);
  const auto& table = reconstruct_param_table();
  for (const auto& name : recipe_param_names()) {
    INFO(name);
    CHECK(table.field(name).get(joint.recon) == table.field(name).get(expected));
  }
  CHECK(joint.recon.line_of_sight_weight == 0.6);
  CHECK(joint.recon.background == Background::Mean);
}

TEST_CASE("Gaga's lift with the KL neighbour regulariser: the term joins every 5th step") {
  const Capture capture = test::rendered_capture();
  const GaussianModel model = test::ground_truth_scene();
  LabelMapSet labels;
  for (const View& v : capture.views) {
    cv::Mat1i m(v.camera.height, v.camera.width, 0);
    m(cv::Rect(0, 0, m.cols / 2, m.rows)) = 1;
    labels.views.push_back({v.name, m});
  }
  labels.labels = 1;
  LabelClassifierOptions o;
  o.iterations = 5;
  o.pixels_per_view = 128;
  const LabelClassifierResult plain = train_label_classifier(model, capture, labels, o);
  o.kl.lambda = 2;
  o.kl.samples = 50;
  const LabelClassifierResult kl = train_label_classifier(model, capture, labels, o);
  // Steps 1-4 are the same; step 5 adds L_3d, so the last loss differs and the features too.
  CHECK(kl.loss_start == plain.loss_start);
  CHECK(kl.loss_end > plain.loss_end);
  CHECK(kl.model.features != plain.model.features);
  o.iterations = 4;
  const LabelClassifierResult four_kl = train_label_classifier(model, capture, labels, o);
  o.kl.lambda = 0;
  CHECK(train_label_classifier(model, capture, labels, o).model.features == four_kl.model.features);
}
