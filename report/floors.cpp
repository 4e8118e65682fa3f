#include "report/floors.hpp"

namespace gslift::report {

const std::vector<MetricFloor>& metric_floors() {
  // The floors hold for the mean over the dev rooms (README "Results"); a single room may sit
  // below them (the main job's seed 0 is the hardest of the five).
  static const std::vector<MetricFloor> floors = {
      {"langor", "eval.mIoU", 70, "issue 11"},
      {"langor", "eval.mLocAcc", 90, "issue 11"},
      {"langor", "eval.mAcc", 75, "issue 11"},
      {"protosaga", "eval.mIoU", 55, "Proto-SaGa's floor (docs/protosaga.md)"},
  };
  return floors;
}

const MetricFloor* find_floor(const std::string& graph, const std::string& metric) {
  for (const MetricFloor& f : metric_floors()) {
    const bool same_graph = graph == f.graph || graph.rfind(f.graph + "_", 0) == 0;
    if (same_graph && metric == f.metric) return &f;
  }
  return nullptr;
}

}  // namespace gslift::report
