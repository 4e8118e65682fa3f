// The report's pictures of a run and a sweep, as inline SVG documents (base/svg.hpp):
// the resolved graph, the timeline of the nodes, and scatter charts with error bars.
#pragma once

#include <string>
#include <vector>

#include "report/records.hpp"

namespace gslift::report {

// The resolved graph in layers (report/layered_layout.hpp), sources on top: one box per node (id,
// type, wall time, cache state; coloured by status) and one arrow per input, labelled by its ports
// ("model" when both ends share the name, else "from→to"). Each box is a group titled with the
// node id (class 'graph-node').
std::string graph_diagram_svg(const RunRecord& run);

// The nodes as they ran: one row per node that started, ordered by start time, its bar from
// start_s to end_s on the run's clock (class 'timeline-bar'), so nodes that ran concurrently
// overlap in x; above them a strip with the number of nodes running at each moment.
std::string timeline_svg(const RunRecord& run);

// One point of a scatter chart: a mean with its standard deviations on both axes.
struct ErrorPoint {
  double x = 0, x_err = 0, y = 0, y_err = 0;
  std::string label;  // tooltip
  std::string tag;    // drawn beside the point (e.g. its row in a table); may be empty
  int series = 0;
};

struct ScatterChart {
  std::string x_label, y_label;
  std::vector<std::string> x_categories;  // non-empty: x is an index into these (a grid param)
  std::vector<std::string> series_names;  // a legend under the plot when more than one
  bool join_series = false;               // a line through each series' points, by x
  bool pareto = false;                    // draw the Pareto front (small x, good y)
  bool lower_y_is_better = false;
  std::vector<ErrorPoint> points;
};

// Points (class 'chart-point') with error bars, axes with ticks, the Pareto front as a dashed
// step line (class 'pareto-front') when asked.
std::string scatter_svg(const ScatterChart& chart);

// Ticks for an axis over [lo, hi]: about `count` round values (1, 2 or 5 times a power of ten).
std::vector<double> nice_ticks(double lo, double hi, int count);

}  // namespace gslift::report
