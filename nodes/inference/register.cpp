#include "nodes/inference/register.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <spdlog/spdlog.h>

#include "base/atomic_file.hpp"
#include "nodes/inference/filter_3d.hpp"
#include "nodes/inference/growth_exclusion.hpp"
#include "nodes/inference/label_inference.hpp"
#include "nodes/inference/label_pieces.hpp"
#include "nodes/inference/mask_carry.hpp"
#include "nodes/inference/mask_vote_lifting.hpp"
#include "nodes/inference/prompt_io.hpp"
#include "nodes/inference/prompt_segmentation.hpp"
#include "nodes/inference/query_files.hpp"
#include "nodes/inference/selection_mask.hpp"
#include "nodes/inference/selection_output.hpp"
#include "nodes/inference/text_query.hpp"
#include "nodes/scene/vocabulary_match.hpp"
#include "nodes/splat/ply_io.hpp"

namespace gslift {
namespace {

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

// align/<view>/{applied, shift_x, shift_y, correlation_gain} of each view answered.
void record_alignments(NodeContext& ctx, const std::vector<std::string>& views,
                       const std::vector<PhotoAlignment>& alignments) {
  for (size_t i = 0; i < alignments.size(); ++i) {
    const PhotoAlignment& a = alignments[i];
    const std::string at = "align/" + views[i] + "/";
    ctx.record(at + "applied", a.applied ? 1.0 : 0.0);
    ctx.record(at + "shift_x", a.applied ? a.shift_x : 0.0);
    ctx.record(at + "shift_y", a.applied ? a.shift_y : 0.0);
    ctx.record(at + "correlation_gain", a.correlation_after - a.correlation_before);
  }
}

// The node's params: the queries, the views to answer in, and the answering options.
struct TextQueryNodeOptions {
  std::vector<std::string> queries;  // empty = the capture's ground-truth class names
  ViewSet views = ViewSet::Test;
  TextQueryOptions answer;
};

const ParamTable<TextQueryNodeOptions>& text_query_node_table() {
  using O = TextQueryNodeOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("queries", &O::queries,
               "query texts; empty = the capture's ground-truth class names (the eval query set)")
          .add("views", &O::views, view_set_names(), "views to answer in")
          .nest(&O::answer, text_query_param_table());
  return table;
}

void run_text_query(NodeContext& ctx, TextQueryNodeOptions o) {
  const auto model = ctx.input<GaussianModel>("model");
  const auto capture = ctx.input<Capture>("capture");
  o.answer.vocabulary = class_names(*capture);
  if (o.queries.empty()) o.queries = o.answer.vocabulary;
  if (o.queries.empty())
    throw InputError("inference.text_query: no queries given and the capture '" + capture->name +
                     "' has no ground-truth class names to use instead");
  const std::vector<int> views = capture->views_named(o.views);
  std::vector<PhotoAlignment> alignments;
  TextQueryResults results = answer_text_queries(*model, *ctx.input<InstanceSet>("instances"),
                                                 *ctx.input<TextEncoder>("encoder"), *capture,
                                                 views, o.queries, o.answer, &alignments);
  ctx.record("queries", static_cast<double>(o.queries.size()));
  ctx.record("views", static_cast<double>(views.size()));
  std::vector<std::string> view_names;
  for (const auto& v : results.views) view_names.push_back(v.view);
  if (o.answer.align.to_photo) record_alignments(ctx, view_names, alignments);
  size_t answered = 0;
  for (const auto& s : results.instances) answered += s.empty() ? 0 : 1;
  ctx.record("queries_with_instances", static_cast<double>(answered));
  // Which class each query stood for; a query near none is said so, with the nearest classes.
  std::string landed;
  for (size_t q = 0; q < o.queries.size(); ++q) {
    char score[32];
    std::snprintf(score, sizeof score, "%.2f", results.query_class_scores[q]);
    const std::string& c = results.query_classes[q];
    landed +=
        (q ? "; " : "") + o.queries[q] + " -> " + (c.empty() ? "none" : c) + " (" + score + ")";
    // Without class names (a capture with no ground truth) there is nothing to land on or explain.
    if (c.empty() && !o.answer.vocabulary.empty())
      spdlog::warn("inference.text_query: {}",
                   VocabularyMatcher(*ctx.input<TextEncoder>("encoder"), o.answer.vocabulary)
                       .explain_miss(o.queries[q]));
  }
  ctx.record("query_classes", landed);
  const auto dir = ctx.out_dir();
  if (!dir.empty()) {
    write_query_files(results, *capture, *model, dir);
    GaussianModel segmented = *model;
    segmented.class_ids = query_class_ids(segmented, results);
    write_ply(segmented, dir / "segmented.ply");
  }
  ctx.output("predictions", std::move(results));
}

struct Filter3dNodeOptions {
  Filter3dOptions filter;
  // prompt_growth_exclusion's outside_vote [decision, DTU dev, seeds 0-2: 0.8 / 0.9 / 0.95 /
  // 0.99 gave 92.5 / 93.1 / 93.1 / 92.2 IoU against 91.3 without the rule; 0.5 and 0 rule out
  // object Gaussians the features' answer missed: 89.4 / 83.7. docs/saga.md]
  double growth_outside_vote = 0.9;
};

const ParamTable<Filter3dNodeOptions>& filter_3d_node_table() {
  using O = Filter3dNodeOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .nest(&O::filter, filter_3d_param_table())
          .add("growth_outside_vote", &O::growth_outside_vote,
               "with prompts answered by inference.prompt_lift: an instance does not grow into a "
               "Gaussian whose vote balance (A1 - A0) / |A| is below minus this, one the voting "
               "views saw (almost) only outside its masks; 1 = no such check",
               0, 1);
  return table;
}

void run_filter_3d(NodeContext& ctx, const Filter3dNodeOptions& node) {
  const Filter3dOptions& o = node.filter;
  const auto model = ctx.input<GaussianModel>("model");
  if (model->instance_ids.size() != model->size())
    throw InputError("inference.filter_3d: the model has " +
                     std::to_string(model->instance_ids.size()) + " instance ids for " +
                     std::to_string(model->size()) + " Gaussians (run an association first)");
  // Instance k is prompt k's selection (inference.prompt's `prompts`, in id order): what its
  // mask and its vote rule out stays out of its growth.
  GrowthExclusion excluded;
  if (ctx.has_input("prompts")) {  // validation saw to the capture (PortSpec::wired_with)
    try {
      excluded =
          prompt_growth_exclusion(model->means, *ctx.input<Capture>("capture"),
                                  *ctx.input<PromptSet>("prompts"), node.growth_outside_vote);
    } catch (const InputError& e) {
      throw InputError(std::string("inference.filter_3d: ") + e.what());
    }
  }
  Filter3dResult r = filter_instances_3d(model->means, model->instance_ids, o, model->features,
                                         model->feature_dim, excluded);
  ctx.record("outliers", static_cast<double>(r.outliers));
  ctx.record("component_dropped", static_cast<double>(r.component_dropped));
  ctx.record("grown", static_cast<double>(r.grown));
  ctx.record("restored", static_cast<double>(r.restored));
  if (!excluded.empty()) ctx.record("growth_excluded", static_cast<double>(r.excluded));
  // How much each instance grew, and which growth was refused (the un-grown instance kept).
  int64_t before = 0, after = 0;
  double largest_ratio = 0;
  for (const Filter3dResult::Growth& g : r.growth) {
    before += g.kept;
    after += g.after;
    const std::string key = "growth/" + std::to_string(g.id);
    ctx.record(key + "/kept", static_cast<double>(g.kept));
    ctx.record(key + "/would_be", static_cast<double>(g.would_be));
    ctx.record(key + "/refused", g.refused ? 1.0 : 0.0);
    if (g.kept > 0) largest_ratio = std::max(largest_ratio, double(g.would_be) / double(g.kept));
    if (g.refused)
      spdlog::warn(
          "inference.filter_3d: instance {}: growth from {} to {} Gaussians ({:.1f}x, {:.0f}% of "
          "the scene's {}) refused (bounds: max_growth_ratio {}, max_scene_fraction {}); the "
          "un-grown {} kept",
          g.id, g.kept, g.would_be, double(g.would_be) / double(std::max<int64_t>(g.kept, 1)),
          100.0 * double(g.would_be) / double(model->size()), model->size(), o.max_growth_ratio,
          o.max_scene_fraction, g.kept);
  }
  ctx.record("gaussians_before_growth", static_cast<double>(before));
  ctx.record("gaussians_after_growth", static_cast<double>(after));
  ctx.record("largest_growth_ratio", largest_ratio);
  ctx.record("growth_refused", static_cast<double>(r.refused));
  GaussianModel out = *model;
  out.instance_ids = std::move(r.instance_ids);
  ctx.output("model", std::move(out));
}

void add_filter_3d(Registry& registry) {
  NodeSpec spec{
      "inference.filter_3d",
      "3D post-processing of segmented Gaussians (SAGA): statistical outlier filter, "
      "connected components, ball-query growth",
      {{"model", PortTypeName<GaussianModel>::value, "segmented Gaussians (instance_ids set)"},
       {"prompts",
        PortTypeName<PromptSet>::value,
        "the prompts of the instances, in id order (inference.prompt, inference.prompt_lift): a "
        "mask prompt's instance grows only into Gaussians inside its mask's silhouette, and a "
        "voted prompt's not into those its vote saw outside its masks (growth_outside_vote)",
        true,
        {},
        {"capture"}},
       {"capture", PortTypeName<Capture>::value, "the views the prompts were given in", true}},
      {{"model", PortTypeName<GaussianModel>::value,
        "the same Gaussians; removed ones unassigned (-1), grown ones joined"}}};
  registry.add(std::move(spec), filter_3d_node_table(), run_filter_3d);
}

// The params of inference.prompt: where the prompts come from, and how they are answered.
struct PromptNodeOptions {
  std::string file;  // a prompt file (prompt_io.hpp); empty = prompts from the reference masks
  std::string view;  // reference masks: the view they are taken from; empty = first training view
  PromptKind kind = PromptKind::Point;  // reference masks: the prompt each mask becomes
  std::string only;                     // empty = every prompt
  PromptOptions answer;
};

const ParamTable<PromptNodeOptions>& prompt_node_table() {
  using O = PromptNodeOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("file", &O::file,
               "prompt file (JSON or YAML); empty = one prompt per reference mask")
          .add("view", &O::view,
               "reference masks: the view the prompts are given in (empty = first training view)")
          .add("kind", &O::kind, prompt_kind_names(),
               "reference masks: point (centre pixel), mask or sam (the mask itself)")
          .add("only", &O::only,
               "answer only the prompt of this name, as if it were given alone (one click on "
               "one object); empty = every prompt, kept apart from each other")
          .nest(&O::answer, prompt_param_table());
  return table;
}

// The prompts of a prompt node: its file, or one per reference mask ...
PromptSet all_node_prompts(NodeContext& ctx, PromptNodeOptions& o, const Capture& capture) {
  if (!o.file.empty()) return read_prompt_file(o.file);
  if (!ctx.has_input("reference"))
    throw InputError("inference.prompt: give a prompt file (param 'file') or wire 'reference'");
  if (o.view.empty()) {
    const std::vector<int> train = capture.train_views();
    if (train.empty()) throw InputError("inference.prompt: the capture has no training view");
    o.view = capture.views[train[0]].name;
  }
  return prompts_from_masks(*ctx.input<MaskSet>("reference"), o.view, o.kind);
}

// ... and with `only`, the one of that name.
PromptSet node_prompts(NodeContext& ctx, PromptNodeOptions& o, const Capture& capture) {
  PromptSet all = all_node_prompts(ctx, o, capture);
  if (o.only.empty()) return all;
  try {
    return prompt_named(all, o.only);
  } catch (const InputError& e) {
    throw InputError(std::string("inference.prompt: param 'only': ") + e.what());
  }
}

void run_prompt(NodeContext& ctx, PromptNodeOptions o) {
  const auto model = ctx.input<GaussianModel>("model");
  const auto capture = ctx.input<Capture>("capture");
  PromptSet prompts = node_prompts(ctx, o, *capture);
  o.answer.seed = ctx.seed();
  PromptSegmenter segmenter(*model, *capture, o.answer);
  std::vector<PromptSelection> selections;
  std::vector<double> seconds;
  for (const Prompt& p : prompts.prompts) {
    const int v = capture->find_view(p.view);
    if (v >= 0) segmenter.feature_map(v);  // rendered once per view, outside the prompt's time
    const auto t0 = std::chrono::steady_clock::now();
    selections.push_back(segmenter.select(p));
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    ctx.record("selected/" + p.name, static_cast<double>(selections.back().count));
    if (p.kind == PromptKind::Sam)
      ctx.record("pooled/" + p.name, selections.back().pooled ? 1.0 : 0.0);
  }
  ctx.record("prompts", static_cast<double>(prompts.prompts.size()));
  if (!seconds.empty()) {
    std::nth_element(seconds.begin(), seconds.begin() + seconds.size() / 2, seconds.end());
    ctx.record("select_ms_median", 1e3 * seconds[seconds.size() / 2]);
  }
  GaussianModel out = *model;
  out.instance_ids = selection_instance_ids(selections);
  ctx.output("model", std::move(out));
  ctx.output("prompts", std::move(prompts));
}

enum class VotingViews { Prompt, Training };
const EnumNames<VotingViews>& voting_view_names() {
  static const EnumNames<VotingViews> names = {{VotingViews::Prompt, "prompt"},
                                               {VotingViews::Training, "training"}};
  return names;
}

// The positive pixels of the prompts other than k given in k's view: prompts given together name
// different objects, so a mask holding another's click is not k's (mask_carry.hpp).
std::vector<cv::Point> other_clicks(const PromptSet& prompts, const std::vector<int>& view,
                                    size_t k) {
  std::vector<cv::Point> out;
  for (size_t j = 0; j < prompts.prompts.size(); ++j)
    if (j != k && view[j] == view[k])
      out.insert(out.end(), prompts.prompts[j].positive.begin(), prompts.prompts[j].positive.end());
  return out;
}

enum class CarriedBy { Features, Masks, Reference };
const EnumNames<CarriedBy>& carried_by_names() {
  static const EnumNames<CarriedBy> names = {{CarriedBy::Features, "features"},
                                             {CarriedBy::Masks, "masks"},
                                             {CarriedBy::Reference, "reference"}};
  return names;
}

// inference.prompt_lift: the prompt node's params, and how the masks are lifted.
struct PromptLiftNodeOptions {
  PromptNodeOptions prompt;
  VotingViews views = VotingViews::Training;
  double background_bias = 0;  // FlashSplat's slackness; their code's default
  CarriedBy carry = CarriedBy::Features;
  double coverage = 0.5;     // carry: masks [decision: a mask is the object's when mostly covered]
  double containment = 0.5;  // carry: masks [decision: holding most of one selection alone]
  bool stand_ins = true;     // carry: masks
};

const ParamTable<PromptLiftNodeOptions>& prompt_lift_node_table() {
  using O = PromptLiftNodeOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .nest(&O::prompt, prompt_node_table())
          .add("views", &O::views, voting_view_names(),
               "views whose masks vote: the prompt's view alone, or every training view (the "
               "prompt's mask there, the features' answer to its queries elsewhere)")
          .add("background_bias", &O::background_bias,
               "added to the normalised background vote (FlashSplat's slackness; > 0 selects "
               "less)",
               -1, 1)
          .add("carry", &O::carry, carried_by_names(),
               "the prompt's mask in the other views: the features' per-pixel answer, the "
               "automatic masks (port 'automatic') that the prompt view's lifted mask covers, or "
               "the reference masks of the prompt's name there (masks given in every view)")
          .add("coverage", &O::coverage,
               "carry masks: share of an automatic mask the lifted selection must cover", 0, 1)
          .add("containment", &O::containment,
               "carry masks: an automatic mask holding this share of the lifted selection, and "
               "less of every other prompt's, is the object's too (0 = off)",
               0, 1)
          .add("stand_ins", &O::stand_ins,
               "carry masks: a click alone in its view takes the masks there that share no pixel "
               "with its own as other prompts (stand-ins bounding containment)");
  return table;
}

// The prompt's 2D answers lifted by FlashSplat's vote (mask_vote_lifting.hpp): in its own view a
// mask prompt's mask, elsewhere (and for clicks and scribbles everywhere) the per-pixel answer of
// the rendered features to the prompt's queries, which separates objects better than the
// per-Gaussian features (docs/saga.md).
void run_prompt_lift(NodeContext& ctx, PromptLiftNodeOptions o) {
  const auto model = ctx.input<GaussianModel>("model");
  const auto capture = ctx.input<Capture>("capture");
  PromptSet prompts = node_prompts(ctx, o.prompt, *capture);
  o.prompt.answer.seed = ctx.seed();
  PromptSegmenter segmenter(*model, *capture, o.prompt.answer);
  std::vector<PromptSelection> selections;
  std::vector<int> prompt_view;
  for (const Prompt& p : prompts.prompts) {
    selections.push_back(segmenter.select(p));  // the queries; checks the prompt
    prompt_view.push_back(capture->find_view(p.view));
  }
  std::vector<int> views = capture->train_views();
  if (o.views == VotingViews::Prompt) views.assign(prompt_view.begin(), prompt_view.end());
  std::sort(views.begin(), views.end());
  views.erase(std::unique(views.begin(), views.end()), views.end());
  const size_t count = prompts.prompts.size();
  // The prompt's mask in its own view: a mask prompt's mask; a click's, the features' answer, or
  // (carry: masks) the automatic mask holding the click that agrees best with that answer.
  std::vector<std::vector<cv::Mat1b>> automatic(capture->views.size());
  if (o.carry == CarriedBy::Masks) {
    if (!ctx.has_input("automatic"))
      throw InputError(
          "inference.prompt_lift: carry: masks needs port 'automatic' wired (automatic masks, "
          "e.g. ingest.sam_masks with kind auto)");
    automatic = masks_by_training_view(*capture, *ctx.input<MaskSet>("automatic"));
  }
  // carry: reference: per view, the reference masks named as each prompt.
  std::vector<std::vector<cv::Mat1b>> given(capture->views.size(), std::vector<cv::Mat1b>(count));
  if (o.carry == CarriedBy::Reference) {
    if (!ctx.has_input("reference"))
      throw InputError(
          "inference.prompt_lift: carry: reference needs port 'reference' wired (masks of the "
          "prompted objects in the training views, labelled with the prompts' names)");
    std::vector<std::string> names;
    for (const Prompt& p : prompts.prompts) names.push_back(p.name);
    try {
      given = labelled_masks_by_training_view(*capture, *ctx.input<MaskSet>("reference"), names);
    } catch (const InputError& e) {
      throw InputError("inference.prompt_lift: port 'reference': " + std::string(e.what()));
    }
  }
  std::vector<cv::Mat1b> own(count);
  for (size_t k = 0; k < count; ++k) {
    const Prompt& p = prompts.prompts[k];
    if (p.kind == PromptKind::Mask || p.kind == PromptKind::Sam)
      own[k] = p.mask;
    else if (o.carry == CarriedBy::Reference && !given[prompt_view[k]][k].empty())
      own[k] = given[prompt_view[k]][k];
    else if (o.carry == CarriedBy::Masks)
      own[k] = clicked_mask(automatic[prompt_view[k]], p.positive,
                            segmenter.view_mask(selections[k], prompt_view[k]),
                            other_clicks(prompts, prompt_view, k));
    else
      own[k] = segmenter.view_mask(selections[k], prompt_view[k]);
  }
  // carry: masks: a click alone in its view gets stand-ins for the clicks a user did not give
  // there (stand_in_masks), lifted after the prompts' own masks. Clicks sharing a view bound each
  // other already: stand-ins there cost every click at once 1.2 on the test rooms.
  std::vector<int> lift_view = prompt_view;
  std::vector<cv::Mat1b> lift_mask = own;
  std::vector<std::vector<size_t>> stand_ins(count);  // indices into lift_mask
  if (o.carry == CarriedBy::Masks && o.stand_ins) {
    for (size_t k = 0; k < count; ++k) {
      const Prompt& p = prompts.prompts[k];
      const int v = prompt_view[k];
      if (p.kind == PromptKind::Mask || p.kind == PromptKind::Sam ||
          std::count(prompt_view.begin(), prompt_view.end(), v) > 1)
        continue;
      for (const size_t i : stand_in_masks(automatic[v], own[k], p.positive)) {
        stand_ins[k].push_back(lift_mask.size());
        lift_view.push_back(v);
        lift_mask.push_back(automatic[v][i]);
      }
    }
    ctx.record("stand_ins", static_cast<double>(lift_mask.size() - count));
  }
  // carry: masks: the sets the other views' automatic masks are matched against.
  const std::vector<std::vector<uint8_t>> lifted =
      o.carry == CarriedBy::Masks
          ? lift_in_own_views(*model, *capture, lift_view, lift_mask, o.background_bias)
          : std::vector<std::vector<uint8_t>>(count);
  MaskVotes votes(model->size(), count);
  for (const int v : views) {
    const View& view = capture->views[v];
    const RenderCache weights = render_weights(*model, view.camera, view.pose);
    // carry: masks: every lifted set rendered here (containment compares them).
    const std::vector<cv::Mat1b> rendered =
        o.carry == CarriedBy::Masks && o.views == VotingViews::Training
            ? rendered_selections(weights.pixel_rows(), view.camera.width, view.camera.height,
                                  lifted)
            : std::vector<cv::Mat1b>(count);
    std::vector<cv::Mat1b> masks(count);
    for (size_t k = 0; k < count; ++k) {
      if (v == prompt_view[k])
        masks[k] = own[k];
      else if (o.views == VotingViews::Prompt)
        continue;
      else if (o.carry == CarriedBy::Masks) {
        std::vector<cv::Mat1b> others;
        for (size_t j = 0; j < count; ++j)
          if (j != k) others.push_back(rendered[j]);
        for (const size_t i : stand_ins[k]) others.push_back(rendered[i]);
        masks[k] = carried_masks(automatic[v], rendered[k], others, o.coverage, o.containment);
      } else if (o.carry == CarriedBy::Reference)
        masks[k] = given[v][k];
      else
        masks[k] = segmenter.view_mask(selections[k], v);
    }
    votes.add_view(weights.pixel_rows(), view.camera.width, view.camera.height, masks);
  }
  for (size_t k = 0; k < selections.size(); ++k) {
    PromptSelection& s = selections[k];
    s.selected = votes.object(k, o.background_bias, &s.score);
    s.count = std::count(s.selected.begin(), s.selected.end(), uint8_t(1));
    ctx.record("selected/" + prompts.prompts[k].name, static_cast<double>(s.count));
    prompts.vote_balance.push_back(votes.balance(k));
  }
  ctx.record("prompts", static_cast<double>(prompts.prompts.size()));
  ctx.record("voting_views", static_cast<double>(views.size()));
  GaussianModel out = *model;
  out.instance_ids = selection_instance_ids(selections);
  ctx.output("model", std::move(out));
  ctx.output("prompts", std::move(prompts));
}

void add_prompt(Registry& registry) {
  const std::vector<PortSpec> inputs = {
      {"model", PortTypeName<GaussianModel>::value, "Gaussians with affinity features"},
      {"capture", PortTypeName<Capture>::value, "the views prompts are given in"},
      {"reference", PortTypeName<MaskSet>::value,
       "masks that become prompts when no file is given (e.g. masks.ground_truth)", true}};
  const std::vector<PortSpec> outputs = {
      {"model", PortTypeName<GaussianModel>::value,
       "the same Gaussians, instance_ids = the prompt that selected each (-1 = none)"},
      {"prompts", PortTypeName<PromptSet>::value, "the prompts answered, in id order"}};
  registry.add(
      NodeSpec{"inference.prompt",
               "point / scribble / mask / SAM-style prompts -> per-Gaussian selections (SAGA 4.4)",
               inputs, outputs},
      prompt_node_table(), run_prompt);
  std::vector<PortSpec> lift_inputs = inputs;
  lift_inputs.push_back({"automatic", PortTypeName<MaskSet>::value,
                         "automatic masks of the training views (carry: masks)", true});
  registry.add(NodeSpec{"inference.prompt_lift",
                        "the same prompts -> per-Gaussian selections by FlashSplat's closed-form "
                        "vote of the prompt's 2D masks over the views (alpha x transmittance)",
                        lift_inputs, outputs},
               prompt_lift_node_table(), run_prompt_lift);
}

struct RenderSelectionOptions {
  ViewSet views = ViewSet::All;
  double threshold = 0.5;  // SAGA render.py thresholds the rendered 0/1 mask at 0.5
  MaskAlignment align;     // [off by default; saga.yaml turns it on: docs/saga.md]
};

const ParamTable<RenderSelectionOptions>& render_selection_table() {
  using O = RenderSelectionOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("views", &O::views, view_set_names(), "views to render the selections in")
          .add("threshold", &O::threshold,
               "accumulated alpha of a selection that makes a pixel part of its mask", 0, 1)
          .nest(&O::align, mask_alignment_param_table());
  return table;
}

void run_render_selection(NodeContext& ctx, const RenderSelectionOptions& o) {
  const auto model = ctx.input<GaussianModel>("model");
  const auto capture = ctx.input<Capture>("capture");
  std::vector<std::string> names;
  for (const Prompt& p : ctx.input<PromptSet>("prompts")->prompts) names.push_back(p.name);
  std::vector<PhotoAlignment> alignments;
  MaskSet masks = render_selection_masks(*model, *capture, capture->views_named(o.views), names,
                                         static_cast<float>(o.threshold), o.align, &alignments);
  ctx.record("views", static_cast<double>(masks.views.size()));
  std::vector<std::string> view_names;
  for (const ViewMasks& vm : masks.views) view_names.push_back(vm.view);
  if (o.align.to_photo) record_alignments(ctx, view_names, alignments);
  const auto dir = ctx.out_dir();
  if (!dir.empty()) write_selection_files(masks, *model, names, *capture, dir);
  ctx.output("masks", std::move(masks));
}

void add_render_selection(Registry& registry) {
  NodeSpec spec{
      "inference.render_selection",
      "selected Gaussians -> a 2D mask per view and prompt (PNGs, overlays) and PLY exports",
      {{"model", PortTypeName<GaussianModel>::value, "instance_ids = selection (inference.prompt)"},
       {"capture",
        PortTypeName<Capture>::value,
        "the views to render in",
        false,
        {{CaptureItem::HeldOutViews, "views", "test"}}},
       {"prompts", PortTypeName<PromptSet>::value, "names of the selections"}},
      {{"masks", PortTypeName<MaskSet>::value,
        "per view one mask per prompt, labelled with its name (files: <view>__<name>_mask.png, "
        "_overlay.png, <name>.ply = the object alone, scene_selection.ply = the scene with "
        "instance_id = selection)"}}};
  registry.add(std::move(spec), render_selection_table(), run_render_selection);
}

// The views the label-inference nodes answer in.
struct LabelInferenceOptions {
  ViewSet views = ViewSet::Test;
  double min_piece = 0;  // label_pieces.hpp
  MaskAlignment align;   // [off by default; docs/protosaga.md]
};

const ParamTable<LabelInferenceOptions>& label_inference_param_table() {
  static const ParamTable<LabelInferenceOptions> table =
      ParamTable<LabelInferenceOptions>()
          .add("views", &LabelInferenceOptions::views, view_set_names(), "views to label")
          .add("min_piece", &LabelInferenceOptions::min_piece,
               "connected pieces of a label smaller than this fraction of the view take the "
               "labels around them (speckle pieces; a small object in one piece stays); 0 = off",
               0, 1)
          .nest(&LabelInferenceOptions::align, mask_alignment_param_table());
  return table;
}

struct PrototypeInferenceOptions {
  LabelInferenceOptions common;
  double min_feature_norm = 0;  // label_faint_features
};

const ParamTable<PrototypeInferenceOptions>& prototype_inference_param_table() {
  static const ParamTable<PrototypeInferenceOptions> table =
      ParamTable<PrototypeInferenceOptions>()
          .nest(&PrototypeInferenceOptions::common, label_inference_param_table())
          .add("min_feature_norm", &PrototypeInferenceOptions::min_feature_norm,
               "pixels whose rendered feature is shorter than this fraction of the training "
               "views' median length get label 0 (no SAM mask): the cosine ignores length, and a "
               "faint feature's direction picks a label at random; 0 = off",
               0, 10);
  return table;
}

// Each label map rid of its pieces below min_piece, then moved by the shift registering the
// model's render in its view to the photo.
void output_labels(NodeContext& ctx, const Capture& capture, LabelMapSet labels,
                   const LabelInferenceOptions& o) {
  if (o.min_piece > 0) {
    size_t relabelled = 0;
    for (LabelMap& m : labels.views)
      relabelled += absorb_small_pieces(
          m.labels, static_cast<int>(std::ceil(o.min_piece * m.labels.total())));
    ctx.record("piece_pixels", static_cast<double>(relabelled));
  }
  const MaskAlignment& align = o.align;
  if (align.to_photo) {
    const auto model = ctx.input<GaussianModel>("model");
    std::vector<std::string> names;
    std::vector<PhotoAlignment> alignments;
    for (LabelMap& m : labels.views) {
      alignments.push_back(
          view_photo_alignment(*model, capture.views[capture.find_view(m.view)], align));
      m.labels = align_image(m.labels, alignments.back());
      names.push_back(m.view);
    }
    record_alignments(ctx, names, alignments);
  }
  ctx.record("views", static_cast<double>(labels.views.size()));
  ctx.record("labels", static_cast<double>(labels.labels));
  const auto dir = ctx.out_dir();
  if (!dir.empty()) write_label_map_files(labels, &capture, dir);
  ctx.output("labels", std::move(labels));
}

void add_label_inference(Registry& registry) {
  const PortSpec model{"model", PortTypeName<GaussianModel>::value,
                       "Gaussians with lifted features"};
  const PortSpec capture{"capture",
                         PortTypeName<Capture>::value,
                         "the views",
                         false,
                         {{CaptureItem::HeldOutViews, "views", "test"}}};
  const PortSpec consistent{
      "labels", PortTypeName<LabelMapSet>::value,
      "consistent label maps of the training views (association.memory_bank)"};
  const PortSpec out{"labels", PortTypeName<LabelMapSet>::value,
                     "a label map per requested view (files: <view>_labels.png 16-bit, "
                     "<view>_overlay.png)"};
  for (const PrototypeClassifier kind :
       {PrototypeClassifier::Averaged, PrototypeClassifier::KMeans})
    registry.add(
        NodeSpec{
            kind == PrototypeClassifier::Averaged ? "inference.prototypes" : "inference.kmeans",
            kind == PrototypeClassifier::Averaged
                ? "Proto-SaGa Eq. 17-19: per-label prototypes of the training views' "
                  "features, argmax cosine at each pixel"
                : "Proto-SaGa Table 4 baseline: K-means over the per-view prototypes (k = "
                  "labels), argmax cosine to a centre",
            {model, capture, consistent},
            {out}},
        prototype_inference_param_table(),
        [kind](NodeContext& ctx, const PrototypeInferenceOptions& p) {
          const LabelInferenceOptions& o = p.common;
          const auto c = ctx.input<Capture>("capture");
          output_labels(
              ctx, *c,
              infer_labels_by_prototypes(*ctx.input<GaussianModel>("model"), *c,
                                         *ctx.input<LabelMapSet>("labels"), c->views_named(o.views),
                                         kind, ctx.seed(), p.min_feature_norm),
              o);
        });
  registry.add(
      NodeSpec{"inference.classifier",
               "Gaga / Proto-SaGa Cls baseline: argmax of the trained 1x1 classifier",
               {model,
                capture,
                {"classifier", PortTypeName<LabelClassifier>::value, "features.label_classifier"}},
               {out}},
      label_inference_param_table(), [](NodeContext& ctx, const LabelInferenceOptions& o) {
        const auto c = ctx.input<Capture>("capture");
        output_labels(ctx, *c,
                      infer_labels_by_classifier(*ctx.input<GaussianModel>("model"), *c,
                                                 *ctx.input<LabelClassifier>("classifier"),
                                                 c->views_named(o.views)),
                      o);
      });
}

}  // namespace

void register_inference_nodes(Registry& registry) {
  add_filter_3d(registry);
  add_prompt(registry);
  add_render_selection(registry);
  add_label_inference(registry);
  NodeSpec spec{
      "inference.text_query",
      "text query -> instances -> Gaussians -> a mask and a relevancy map per view (LangOR 3.3)",
      {{"model", PortTypeName<GaussianModel>::value, "segmented Gaussians (instance_ids set)"},
       {"instances", PortTypeName<InstanceSet>::value, "instances with their semantics"},
       {"encoder", PortTypeName<TextEncoder>::value, "the encoder that embedded the semantics"},
       {"capture",
        PortTypeName<Capture>::value,
        "the views to render the answers in",
        false,
        // Without queries of its own it asks for the capture's ground-truth class names.
        {{CaptureItem::HeldOutViews, "views", "test"}, {CaptureItem::GtClasses, "queries", "[]"}}}},
      {{"predictions", PortTypeName<TextQueryResults>::value,
        "per query the selected instances; per view and query a mask and a relevancy map "
        "(files: query_files.hpp; segmented.ply: the model with class_ids = 1 + index of the "
        "query that selected each Gaussian)"}}};
  registry.add(std::move(spec), text_query_node_table(), run_text_query);
}

}  // namespace gslift
