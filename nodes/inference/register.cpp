#include "nodes/inference/register.hpp"

#include <nlohmann/json.hpp>

#include "nodes/inference/filter_3d.hpp"
#include "nodes/inference/query_files.hpp"
#include "nodes/inference/text_query.hpp"
#include "nodes/splat/ply_io.hpp"
#include "runtime/atomic_file.hpp"

namespace gslift {
namespace {

std::vector<int> select_views(const Capture& capture, const std::string& which) {
  if (which == "train") return capture.train_views();
  if (which == "test") return capture.test_views();
  std::vector<int> all(capture.views.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  return all;
}

std::vector<std::string> class_names(const Capture& capture) {
  std::vector<std::string> names;
  for (const auto& [id, name] : capture.classes)
    if (id != 0) names.push_back(name);
  return names;
}

// Class id of each Gaussian: 1 + the index of the query whose selection holds its instance, -1
// when none (queries.json maps the ids back to the query texts).
std::vector<int32_t> query_class_ids(const GaussianModel& model, const TextQueryResults& r) {
  std::vector<int32_t> instance_class(
      static_cast<size_t>(r.relevancy.empty() ? 0 : r.relevancy[0].size()), -1);
  for (size_t q = 0; q < r.instances.size(); ++q)
    for (int k : r.instances[q])
      if (instance_class[k] < 0) instance_class[k] = static_cast<int32_t>(q + 1);
  std::vector<int32_t> ids(model.size(), -1);
  for (size_t g = 0; g < model.size(); ++g) {
    const int32_t k = model.instance_ids[g];
    if (k >= 0 && static_cast<size_t>(k) < instance_class.size()) ids[g] = instance_class[k];
  }
  return ids;
}

void run_filter_3d(NodeContext& ctx, const Filter3dOptions& o) {
  const auto model = ctx.input<GaussianModel>("model");
  if (model->instance_ids.size() != model->size())
    throw InputError("inference.filter_3d: the model has " +
                     std::to_string(model->instance_ids.size()) + " instance ids for " +
                     std::to_string(model->size()) + " Gaussians (run an association first)");
  Filter3dResult r = filter_instances_3d(model->means, model->instance_ids, o);
  ctx.record("outliers", static_cast<double>(r.outliers));
  ctx.record("component_dropped", static_cast<double>(r.component_dropped));
  ctx.record("grown", static_cast<double>(r.grown));
  ctx.record("restored", static_cast<double>(r.restored));
  GaussianModel out = *model;
  out.instance_ids = std::move(r.instance_ids);
  ctx.output("model", std::move(out));
}

void add_filter_3d(Registry& registry) {
  NodeSpec spec{
      "inference.filter_3d",
      "3D post-processing of segmented Gaussians (SAGA): statistical outlier filter, "
      "connected components, ball-query growth",
      {{"model", PortTypeName<GaussianModel>::value, "segmented Gaussians (instance_ids set)"}},
      {{"model", PortTypeName<GaussianModel>::value,
        "the same Gaussians; removed ones unassigned (-1), grown ones joined"}}};
  registry.add(std::move(spec), filter_3d_param_table(), run_filter_3d);
}

}  // namespace

void register_inference_nodes(Registry& registry) {
  add_filter_3d(registry);
  const TextQueryOptions d;
  ParamSpec queries;
  queries.name = "queries";
  queries.type = ParamType::StringList;
  queries.default_value = std::vector<std::string>{};
  queries.doc = "query texts; empty = the capture's ground-truth class names (the eval query set)";
  NodeSpec spec{
      "inference.text_query",
      "text query -> instances -> Gaussians -> a mask and a relevancy map per view (LangOR 3.3)",
      {{"model", PortTypeName<GaussianModel>::value, "segmented Gaussians (instance_ids set)"},
       {"instances", PortTypeName<InstanceSet>::value, "instances with their semantics"},
       {"encoder", PortTypeName<TextEncoder>::value, "the encoder that embedded the semantics"},
       {"capture", PortTypeName<Capture>::value, "the views to render the answers in"}},
      {{"predictions", PortTypeName<TextQueryResults>::value,
        "per query the selected instances; per view and query a mask and a relevancy map "
        "(files: query_files.hpp; segmented.ply: the model with class_ids = 1 + index of the "
        "query that selected each Gaussian)"}},
      {queries, string_param("views", "test", "views to answer in", {"test", "train", "all"}),
       string_param("selection", d.selection,
                    "closed_set: argmax over the query vocabulary (plus the capture's class "
                    "names), beating the canonical negatives; relevancy: relevancy > "
                    "relevancy_threshold",
                    {"closed_set", "relevancy"}),
       float_param("relevancy_threshold", d.relevancy_threshold,
                   "selection=relevancy: minimum LangSplat relevancy of a selected instance", 0, 1),
       float_param("mask_threshold", d.mask_threshold,
                   "accumulated alpha of the selected Gaussians that puts a pixel in the mask", 0,
                   1),
       bool_param("normalise_relevancy", d.normalise_relevancy,
                  "relevancy map = weighted mean of instance relevancies (divided by the "
                  "accumulated alpha) instead of the weighted sum"),
       float_param("softmax_scale", d.softmax_scale,
                   "temperature of the relevancy softmax "
                   "(LangSplat: 10)",
                   0.1, 1000)}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    const auto model = ctx.input<GaussianModel>("model");
    const auto instances = ctx.input<InstanceSet>("instances");
    const auto encoder = ctx.input<TextEncoder>("encoder");
    const auto capture = ctx.input<Capture>("capture");
    TextQueryOptions o;
    o.selection = ctx.param_string("selection");
    o.relevancy_threshold = static_cast<float>(ctx.param_float("relevancy_threshold"));
    o.mask_threshold = static_cast<float>(ctx.param_float("mask_threshold"));
    o.softmax_scale = static_cast<float>(ctx.param_float("softmax_scale"));
    o.normalise_relevancy = ctx.param_bool("normalise_relevancy");
    o.vocabulary = class_names(*capture);
    std::vector<std::string> queries = ctx.param_strings("queries");
    if (queries.empty()) queries = o.vocabulary;
    if (queries.empty())
      throw InputError("inference.text_query: no queries given and the capture '" + capture->name +
                       "' has no ground-truth class names to use instead");
    const std::vector<int> views = select_views(*capture, ctx.param_string("views"));
    TextQueryResults results =
        answer_text_queries(*model, *instances, *encoder, *capture, views, queries, o);
    ctx.record("queries", static_cast<double>(queries.size()));
    ctx.record("views", static_cast<double>(views.size()));
    size_t answered = 0;
    for (const auto& s : results.instances) answered += s.empty() ? 0 : 1;
    ctx.record("queries_with_instances", static_cast<double>(answered));
    const auto dir = ctx.out_dir();
    if (!dir.empty()) {
      write_query_files(results, *capture, dir);
      GaussianModel segmented = *model;
      segmented.class_ids = query_class_ids(segmented, results);
      write_ply(segmented, dir / "segmented.ply");
    }
    ctx.output("predictions", std::move(results));
  });
}

}  // namespace gslift
