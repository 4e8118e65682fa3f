// The accuracy floors the README's Results holds each method to, declared once: `gslift report`
// puts a run's headline metrics beside them, and README.md cites this table.
#pragma once

#include <string>
#include <vector>

namespace gslift::report {

struct MetricFloor {
  std::string graph;   // the graph's name; its ablations ("<graph>_<variant>") share the floors
  std::string metric;  // "<eval node id>.<record>", as headline_metrics names it
  double floor = 0;    // the metric must be at least this (percent)
  std::string source;  // where the floor was set
};

// Every floor, in the README's order.
const std::vector<MetricFloor>& metric_floors();

// The floor for a metric of a run of `graph`; null when there is none.
const MetricFloor* find_floor(const std::string& graph, const std::string& metric);

}  // namespace gslift::report
