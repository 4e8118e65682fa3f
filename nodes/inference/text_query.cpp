#include "nodes/inference/text_query.hpp"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <opencv2/core.hpp>

#include "base/errors.hpp"
#include "nodes/scene/vocabulary_match.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {
namespace {

RenderOutput weights_pass(const GaussianModel& model, const Camera& camera, const Pose& pose) {
  RenderSettings settings;
  settings.rgb = false;  // only the blend weights are kept
  return render(model, camera, pose, settings);
}

Eigen::MatrixXf encode_rows(const TextEncoder& encoder, const std::vector<std::string>& texts) {
  Eigen::MatrixXf m(static_cast<Eigen::Index>(texts.size()), encoder.dim());
  for (size_t i = 0; i < texts.size(); ++i) m.row(i) = encoder.encode(texts[i]).transpose();
  return m;
}

}  // namespace

QueryView::QueryView(const GaussianModel& model, const Camera& camera, const Pose& pose)
    : cache_(weights_pass(model, camera, pose)) {
  const auto& ids = model.instance_ids;
  if (ids.size() != model.size()) return;
  const int32_t max_id = ids.empty() ? -1 : *std::max_element(ids.begin(), ids.end());
  for (int32_t k = 0; k <= max_id; ++k)
    instance_alpha_.emplace_back(cv::Mat1f::zeros(cache_.height(), cache_.width()));
  // Each pixel's row is summed by one task, so the planes do not depend on the thread count.
  const auto& off = cache_.pixel_offsets();
  const auto& entry_ids = cache_.ids();
  const auto& w = cache_.weights();
  tbb::parallel_for(size_t(0), off.size() - 1, [&](size_t p) {
    for (uint32_t e = off[p]; e < off[p + 1]; ++e) {
      const int32_t k = ids[entry_ids[e]];
      if (k >= 0) reinterpret_cast<float*>(instance_alpha_[k].data)[p] += w[e];
    }
  });
}

cv::Mat1f QueryView::render(const std::vector<float>& per_gaussian) const {
  if (per_gaussian.size() != cache_.gaussian_count())
    throw InputError("text query: " + std::to_string(per_gaussian.size()) +
                     " per-Gaussian values for a model of " +
                     std::to_string(cache_.gaussian_count()) + " Gaussians");
  cv::Mat1f out(cache_.height(), cache_.width());
  cache_.render(per_gaussian.data(), 1, out.ptr<float>());
  return out;
}

cv::Mat1b QueryView::mask(const std::vector<float>& indicator, float threshold) const {
  cv::Mat1b m;
  cv::compare(render(indicator), threshold, m, cv::CMP_GE);
  return m;
}

cv::Mat1f QueryView::render_instances(const Eigen::VectorXf& per_instance) const {
  cv::Mat1f out = cv::Mat1f::zeros(cache_.height(), cache_.width());
  const Eigen::Index n = std::min<Eigen::Index>(per_instance.size(), instance_alpha_.size());
  for (Eigen::Index k = 0; k < n; ++k)
    if (per_instance[k] != 0.f) cv::scaleAdd(instance_alpha_[k], per_instance[k], out, out);
  return out;
}

cv::Mat1b QueryView::instance_mask(const std::vector<int>& instances, float threshold) const {
  cv::Mat1f alpha = cv::Mat1f::zeros(cache_.height(), cache_.width());
  for (int k : instances)
    if (k >= 0 && k < static_cast<int>(instance_alpha_.size())) alpha += instance_alpha_[k];
  cv::Mat1b m;
  cv::compare(alpha, threshold, m, cv::CMP_GE);
  return m;
}

std::vector<float> gaussian_values(const std::vector<int32_t>& instance_ids,
                                   const Eigen::VectorXf& per_instance) {
  std::vector<float> v(instance_ids.size(), 0.f);
  for (size_t g = 0; g < instance_ids.size(); ++g) {
    const int32_t id = instance_ids[g];
    if (id >= 0 && id < per_instance.size()) v[g] = per_instance[id];
  }
  return v;
}

std::vector<float> selection_indicator(const std::vector<int32_t>& instance_ids, int instance_count,
                                       const std::vector<int>& instances) {
  Eigen::VectorXf chosen = Eigen::VectorXf::Zero(instance_count);
  for (int k : instances) chosen[k] = 1.f;
  return gaussian_values(instance_ids, chosen);
}

void select_instances(const InstanceSet& instances, const TextEncoder& encoder,
                      const TextQueryOptions& options, TextQueryResults& results) {
  if (instances.size() > 0 && instances.semantics.rows() != instances.size())
    throw InputError("text query: " + std::to_string(instances.semantics.rows()) +
                     " semantics rows for " + std::to_string(instances.size()) + " instances");
  if (instances.semantics.rows() > 0 && instances.semantics.cols() != encoder.dim())
    throw InputError("text query: instance semantics are " +
                     std::to_string(instances.semantics.cols()) + "-d but the encoder '" +
                     encoder.name() + "' gives " + std::to_string(encoder.dim()) +
                     "-d embeddings (labels and queries must share one encoder)");
  const Eigen::MatrixXf semantics =
      instances.semantics.rows() > 0 ? instances.semantics : Eigen::MatrixXf(0, encoder.dim());
  const Eigen::MatrixXf negatives = encode_rows(encoder, options.negatives);
  const size_t q_count = results.queries.size();
  results.query_classes.assign(q_count, "");
  results.query_class_scores.assign(q_count, 0.f);
  if (!options.vocabulary.empty()) {
    const VocabularyMatcher matcher(encoder, options.vocabulary);
    for (size_t q = 0; q < q_count; ++q) {
      const ClassMatch best = matcher.rank(results.queries[q]).front();
      results.query_class_scores[q] = best.score;
      if (best.score >= matcher.threshold()) results.query_classes[q] = best.name;
    }
  }
  results.relevancy.clear();
  for (const auto& q : results.queries)
    results.relevancy.push_back(
        instance_relevancy(semantics, encoder.encode(q), negatives, options.softmax_scale));
  if (options.selection == QuerySelection::Relevancy) {
    results.instances.clear();
    for (const auto& r : results.relevancy)
      results.instances.push_back(relevancy_selection(r, options.relevancy_threshold));
    return;
  }
  // Closed set over the queries followed by the extra vocabulary entries that no query stands for.
  std::vector<std::string> vocabulary = results.queries;
  for (const auto& v : options.vocabulary)
    if (std::find(vocabulary.begin(), vocabulary.end(), v) == vocabulary.end() &&
        std::find(results.query_classes.begin(), results.query_classes.end(), v) ==
            results.query_classes.end())
      vocabulary.push_back(v);
  auto selected = closed_set_selection(semantics, encode_rows(encoder, vocabulary), negatives,
                                       options.softmax_scale);
  selected.resize(q_count);
  results.instances = std::move(selected);
}

TextQueryResults answer_text_queries(const GaussianModel& model, const InstanceSet& instances,
                                     const TextEncoder& encoder, const Capture& capture,
                                     const std::vector<int>& view_indices,
                                     const std::vector<std::string>& queries,
                                     const TextQueryOptions& options,
                                     std::vector<PhotoAlignment>* alignments) {
  if (model.instance_ids.size() != model.size())
    throw InputError("text query: the model has " + std::to_string(model.instance_ids.size()) +
                     " instance ids for " + std::to_string(model.size()) +
                     " Gaussians (segment it first, e.g. association.instance_mask_gaussian)");
  for (int32_t id : model.instance_ids)
    if (id < -1 || id >= instances.size())
      throw InputError("text query: Gaussian instance id " + std::to_string(id) +
                       " is outside the " + std::to_string(instances.size()) + " instances");
  TextQueryResults results;
  results.queries = queries;
  if (alignments) alignments->clear();
  select_instances(instances, encoder, options, results);

  for (int vi : view_indices) {
    const View& view = capture.views.at(static_cast<size_t>(vi));
    const QueryView qv(model, view.camera, view.pose);
    const PhotoAlignment alignment = view_photo_alignment(model, view, options.align);
    if (alignments) alignments->push_back(alignment);
    TextQueryResults::ViewAnswers answers;
    answers.view = view.name;
    cv::Mat1f alpha;
    if (options.normalise_relevancy)
      alpha = cv::max(qv.render(std::vector<float>(model.size(), 1.f)), 1e-6f);
    for (size_t q = 0; q < queries.size(); ++q) {
      answers.masks.push_back(
          align_image(qv.instance_mask(results.instances[q], options.mask_threshold), alignment));
      cv::Mat1f relevancy = qv.render_instances(results.relevancy[q]);
      if (options.normalise_relevancy) relevancy /= alpha;
      answers.relevancy.push_back(align_image(relevancy, alignment));
    }
    results.views.push_back(std::move(answers));
  }
  return results;
}

const EnumNames<QuerySelection>& query_selection_names() {
  static const EnumNames<QuerySelection> names = {{QuerySelection::ClosedSet, "closed_set"},
                                                  {QuerySelection::Relevancy, "relevancy"}};
  return names;
}

const ParamTable<TextQueryOptions>& text_query_param_table() {
  using O = TextQueryOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("selection", &O::selection, query_selection_names(),
               "closed_set: argmax over the query vocabulary (plus the capture's class names), "
               "beating the canonical negatives; relevancy: relevancy > relevancy_threshold")
          .add("relevancy_threshold", &O::relevancy_threshold,
               "selection=relevancy: minimum LangSplat relevancy of a selected instance", 0, 1)
          .add("mask_threshold", &O::mask_threshold,
               "accumulated alpha of the selected Gaussians that puts a pixel in the mask", 0, 1)
          .add("normalise_relevancy", &O::normalise_relevancy,
               "relevancy map = weighted mean of instance relevancies (divided by the accumulated "
               "alpha) instead of the weighted sum")
          .add("softmax_scale", &O::softmax_scale,
               "temperature of the relevancy softmax (LangSplat: 10)", 0.1, 1000)
          .nest(&O::align, mask_alignment_param_table());
  return table;
}

}  // namespace gslift
