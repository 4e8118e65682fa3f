#include "nodes/eval/langor_eval.hpp"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <sstream>

#include "base/errors.hpp"
#include "base/fixed_point.hpp"

namespace gslift {
namespace {

struct Row {
  std::string name;
  std::string queries;
  double iou, loc, loc_box, acc;
};

std::vector<Row> table_rows(const LangorSummary& s) {
  std::vector<Row> rows;
  double loc = 0, loc_box = 0;
  for (const auto& c : s.classes) {
    rows.push_back({c.label, std::to_string(c.queries), c.iou, c.loc_acc, c.loc_acc_box, c.acc});
    loc += c.loc_acc;
    loc_box += c.loc_acc_box;
  }
  const double k = s.classes.empty() ? 1.0 : static_cast<double>(s.classes.size());
  rows.push_back({"mean over classes", std::to_string(s.classes.size()), s.miou_class, loc / k,
                  loc_box / k, s.macc});
  rows.push_back(
      {"mean over queries", std::to_string(s.queries), s.miou, s.mlocacc, s.mlocacc_box, s.macc});
  return rows;
}

}  // namespace

std::optional<size_t> query_for_class(const TextQueryResults& predictions,
                                      const std::string& class_name) {
  const auto& q = predictions.queries;
  if (const auto named = std::find(q.begin(), q.end(), class_name); named != q.end())
    return static_cast<size_t>(named - q.begin());
  const auto& c = predictions.query_classes;
  if (const auto landed = std::find(c.begin(), c.end(), class_name); landed != c.end())
    return static_cast<size_t>(landed - c.begin());
  return std::nullopt;
}

std::vector<std::string> langor_unqueried_classes(const TextQueryResults& predictions,
                                                  const Capture& capture) {
  std::vector<std::string> out;
  for (const auto& [class_id, name] : capture.classes)
    if (class_id != 0 && !query_for_class(predictions, name)) out.push_back(name);
  return out;
}

std::vector<QueryScore> score_langor(const TextQueryResults& predictions, const Capture& capture,
                                     const LangorEvalOptions& options) {
  std::vector<QueryScore> scores;
  int evaluated_views = 0;
  for (int vi : capture.test_views()) {
    const View& view = capture.views[vi];
    if (!view.gt_semantic.present()) continue;
    const cv::Mat semantic = view.gt_semantic.load();
    ++evaluated_views;
    const auto answers = std::find_if(predictions.views.begin(), predictions.views.end(),
                                      [&](const auto& a) { return a.view == view.name; });
    for (const auto& [class_id, name] : capture.classes) {
      if (class_id == 0) continue;
      cv::Mat1b gt;
      cv::compare(semantic, class_id, gt, cv::CMP_EQ);
      if (cv::countNonZero(gt) < options.min_gt_pixels) continue;
      if (answers == predictions.views.end())
        throw InputError("eval.langor: no predictions for the held-out view '" + view.name +
                         "' (run the text query with views: test or all)");
      const std::optional<size_t> found = query_for_class(predictions, name);
      if (!found) continue;  // not asked about: left out (langor_unqueried_classes)
      const size_t qi = *found;
      const cv::Mat1b& pred = answers->masks[qi];
      const cv::Mat1f& rel = answers->relevancy[qi];
      if (pred.size() != gt.size() || rel.size() != gt.size())
        throw InputError("eval.langor: predictions for view '" + view.name + "' are " +
                         std::to_string(pred.cols) + "x" + std::to_string(pred.rows) +
                         " but its ground truth is " + std::to_string(gt.cols) + "x" +
                         std::to_string(gt.rows));
      QueryScore s;
      s.view = view.name;
      s.label = name;
      s.counts = compare_masks(pred, gt);
      s.localised = localised_in_mask(rel, gt);
      s.localised_box = localised_in_box(rel, gt, options.loc_box);
      scores.push_back(std::move(s));
    }
  }
  if (evaluated_views == 0)
    throw InputError("eval.langor: the capture '" + capture.name +
                     "' has no held-out view with a ground-truth semantic map");
  if (scores.empty()) {
    std::string queries;
    for (const auto& q : predictions.queries) queries += (queries.empty() ? "'" : ", '") + q + "'";
    throw InputError(
        "eval.langor: no query names or lands on a class present in the held-out "
        "views (queries: " +
        queries + ")");
  }
  return scores;
}

std::string langor_table_csv(const LangorSummary& s) {
  std::ostringstream out;
  out << "class,queries,iou,loc_acc,loc_acc_box,acc\n";
  for (const Row& r : table_rows(s))
    out << '"' << r.name << "\"," << r.queries << ',' << fixed2(r.iou) << ',' << fixed2(r.loc)
        << ',' << fixed2(r.loc_box) << ',' << fixed2(r.acc) << '\n';
  return out.str();
}

std::string langor_table_markdown(const LangorSummary& s) {
  std::ostringstream out;
  out << "| class | queries | IoU | LocAcc | LocAcc (box) | Acc "
         "|\n|---|---:|---:|---:|---:|---:|\n";
  for (const Row& r : table_rows(s))
    out << "| " << r.name << " | " << r.queries << " | " << fixed2(r.iou) << " | " << fixed2(r.loc)
        << " | " << fixed2(r.loc_box) << " | " << fixed2(r.acc) << " |\n";
  return out.str();
}

const ParamTable<LangorEvalOptions>& langor_eval_param_table() {
  using O = LangorEvalOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("min_gt_pixels", &O::min_gt_pixels,
               "a class is present in a view (hence queried) from this many GT pixels on", 1)
          .add("loc_box", &O::loc_box,
               "box filter width of LangSplat's localisation variant (mLocAcc_box)", 1, 1000);
  return table;
}

}  // namespace gslift
