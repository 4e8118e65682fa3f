// eval.langor's protocol over a capture with ground truth: for every held-out view
// and every class present in its semantic map (at least min_gt_pixels pixels [decision]: a sliver
// at the image border is not an annotated object), the query is the class name; the prediction is
// the text query's mask and relevancy map for that (view, query).
//
// With the user's own queries (issue 30) [decision]: a class is scored through the query that
// names it, else the first query that lands on it (TextQueryResults::query_classes: "ventilator"
// is scored as the anesthesia machine); a class no query names or lands on is left out of the
// table and listed (langor_unqueried_classes), since a user who asked about three things expects
// those three measured, not a failed run. The paper's protocol is the default query set, every
// class name.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "nodes/eval/langor_metrics.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/text_query_results.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct LangorEvalOptions {
  int min_gt_pixels = 100;  // a class counts as present in a view from this many pixels on
  int loc_box = 30;         // LangSplat's box filter width for mLocAcc_box
};

// The params of eval.langor: one entry per field above.
const ParamTable<LangorEvalOptions>& langor_eval_param_table();

// The query that stands for `class_name`: the one equal to it, else the first that landed on it.
std::optional<size_t> query_for_class(const TextQueryResults& predictions,
                                      const std::string& class_name);
// The capture's classes (id != 0) that no query stands for.
std::vector<std::string> langor_unqueried_classes(const TextQueryResults& predictions,
                                                  const Capture& capture);

// Scores every (held-out view, present class with a query). Throws InputError when the capture
// has no held-out view with ground truth, when the predictions lack a needed view, or when no
// present class has a query at all.
std::vector<QueryScore> score_langor(const TextQueryResults& predictions, const Capture& capture,
                                     const LangorEvalOptions& options);

// The metrics table: one row per class, then the mean row ("mean": per-class means for IoU,
// LocAcc and Acc; and "all queries": the per-query means the papers report as mIoU/mLocAcc).
std::string langor_table_csv(const LangorSummary& s);
std::string langor_table_markdown(const LangorSummary& s);

}  // namespace gslift
