#include "report/charts.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "base/svg.hpp"
#include "report/layered_layout.hpp"
#include "report/pareto.hpp"
#include "report/timeline.hpp"

namespace gslift::report {

namespace {

std::string num(double v) {
  return Svg::number(std::round(v * 100) / 100);
}

// Width of a label in the SVG's sans-serif: an estimate (no font metrics without a browser),
// generous so that text stays inside its box.
double text_width(const std::string& text, double font_size) {
  return 0.62 * font_size * double(text.size());
}

struct StatusStyle {
  const char* fill;
  const char* stroke;
};

StatusStyle status_style(const std::string& status) {
  if (status == "ok") return {"#e8f3ea", "#3d8b4f"};
  if (status == "failed") return {"#fbe4e1", "#c0392b"};
  return {"#eeeeee", "#8a8a8a"};  // cancelled, pending
}

const char* const kPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};

std::string series_colour(int series) {
  return kPalette[series % 10];
}

std::string seconds_text(double s) {
  if (s < 0.01) return Svg::number(std::round(s * 1e4) / 10) + " ms";
  if (s < 10) return Svg::number(std::round(s * 100) / 100) + " s";
  return Svg::number(std::round(s * 10) / 10) + " s";
}

}  // namespace

std::vector<double> nice_ticks(double lo, double hi, int count) {
  if (!(hi > lo)) return {lo};
  const double raw = (hi - lo) / std::max(1, count);
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = power;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (raw <= m * power) {
      step = m * power;
      break;
    }
  // Multiples of the step, so that no rounding error accumulates along the axis.
  std::vector<double> ticks;
  const double first = std::ceil(lo / step - 1e-9), last = std::floor(hi / step + 1e-9);
  for (double k = first; k <= last; ++k) ticks.push_back(k == 0 ? 0.0 : k * step);
  return ticks;
}

std::string graph_diagram_svg(const RunRecord& run) {
  const size_t n = run.graph.size();
  std::map<std::string, int> index;
  for (size_t i = 0; i < n; ++i) index[run.graph[i].id] = int(i);
  struct Edge {
    int from, to;
    std::string from_port, label;
    double label_w = 0, entry_x = 0;
  };
  std::vector<Edge> edges;
  std::vector<std::pair<int, int>> pairs;
  std::vector<double> inputs_w(n, 0);
  for (size_t i = 0; i < n; ++i)
    for (const auto& [port, ref] : run.graph[i].inputs) {
      const auto dot = ref.find('.');
      const auto it = index.find(ref.substr(0, dot));
      if (it == index.end()) continue;
      const std::string from_port = dot == std::string::npos ? "" : ref.substr(dot + 1);
      const std::string label = from_port == port ? port : from_port + "\u2192" + port;
      const double w = text_width(label, 10) + 8;
      edges.push_back({it->second, int(i), from_port, label, w});
      pairs.push_back({it->second, int(i)});
      inputs_w[i] += w;
    }

  // Boxes wide enough for their text and for their inputs' labels side by side.
  constexpr double kBoxH = 46, kLayerGap = 58, kGap = 26, kMargin = 16;
  std::vector<std::string> line2(n);
  std::vector<double> width(n);
  for (size_t i = 0; i < n; ++i) {
    const NodeRun* r = run.node(run.graph[i].id);
    line2[i] = run.graph[i].type;
    if (r && r->status != "pending") line2[i] += " \u00b7 " + seconds_text(r->wall_s);
    if (r && !r->cache.empty()) line2[i] += " \u00b7 cache " + r->cache;
    width[i] = std::max({text_width(run.graph[i].id, 13) + 20, text_width(line2[i], 11) + 20,
                         inputs_w[i] + 12, 80.0});
  }
  const LayeredLayout layout = layered_layout(width, pairs, kGap);
  const auto X = [&](double x) { return kMargin + x; };
  const auto top = [&](int layer) { return kMargin + double(layer) * (kBoxH + kLayerGap); };
  const double total_h = top(int(layout.order.size())) - kLayerGap + kMargin;
  Svg svg(layout.width + 2 * kMargin, std::max(total_h, 60.0), 12);

  // Where each edge meets its target: the labels side by side along the top edge, ordered by
  // where the edges come from so that they do not cross at the box.
  const auto approach_x = [&](size_t e) {
    return layout.route[e].empty() ? X(layout.x[edges[e].from]) + width[edges[e].from] / 2
                                   : X(layout.route[e].back());
  };
  std::map<int, std::vector<size_t>> incoming;
  for (size_t e = 0; e < edges.size(); ++e) incoming[edges[e].to].push_back(e);
  for (auto& [node, list] : incoming) {
    std::stable_sort(list.begin(), list.end(),
                     [&](size_t a, size_t b) { return approach_x(a) < approach_x(b); });
    double at = X(layout.x[node]) + (width[node] - inputs_w[node]) / 2;
    for (size_t e : list) {
      edges[e].entry_x = at + edges[e].label_w / 2;
      at += edges[e].label_w;
    }
  }
  // Each output port leaves from its own point along the bottom edge.
  std::map<int, std::vector<std::string>> out_ports;
  for (const auto& e : edges) {
    auto& ports = out_ports[e.from];
    if (std::find(ports.begin(), ports.end(), e.from_port) == ports.end())
      ports.push_back(e.from_port);
  }
  const auto curve = [&](double x1, double y1, double x2, double y2) {
    const double bend = (y2 - y1) * 0.5;
    return " C " + num(x1) + " " + num(y1 + bend) + " " + num(x2) + " " + num(y2 - bend) + " " +
           num(x2) + " " + num(y2);
  };
  for (size_t k = 0; k < edges.size(); ++k) {
    const Edge& e = edges[k];
    const auto& ports = out_ports[e.from];
    const size_t p = std::find(ports.begin(), ports.end(), e.from_port) - ports.begin();
    double x = X(layout.x[e.from]) + width[e.from] * double(p + 1) / double(ports.size() + 1);
    double y = top(layout.layer[e.from]) + kBoxH;
    std::string d = "M " + num(x) + " " + num(y);
    int layer = layout.layer[e.from];
    for (double lane : layout.route[k]) {  // through its lane on each layer it crosses
      ++layer;
      d += curve(x, y, X(lane), top(layer)) + " L " + num(X(lane)) + " " + num(top(layer) + kBoxH);
      x = X(lane), y = top(layer) + kBoxH;
    }
    const double y2 = top(layout.layer[e.to]) - 1;
    d += curve(x, y, e.entry_x, y2);
    svg.path(d, "#8795a1", "stroke-width='1.3' class='graph-edge'");
    svg.line(e.entry_x - 3.5, y2 - 6, e.entry_x, y2, "#8795a1", "stroke-width='1.3'");
    svg.line(e.entry_x + 3.5, y2 - 6, e.entry_x, y2, "#8795a1", "stroke-width='1.3'");
  }
  for (const auto& e : edges)
    svg.text(e.entry_x, top(layout.layer[e.to]) - 10, e.label,
             "text-anchor='middle' font-size='10' fill='#3e4a55' stroke='white' "
             "stroke-width='3' paint-order='stroke'");
  for (size_t i = 0; i < n; ++i) {
    const NodeRun* r = run.node(run.graph[i].id);
    const std::string status = r ? r->status : "pending";
    const StatusStyle style = status_style(status);
    std::string tip = run.graph[i].id + " (" + run.graph[i].type + "): " + status;
    if (!run.graph[i].loc.empty()) tip += "\n" + run.graph[i].loc;
    if (r && !r->error.empty()) tip += "\n" + r->error;
    const double x = X(layout.x[i]), y = top(layout.layer[i]);
    svg.begin_group(tip, "class='graph-node'");
    svg.rect(x, y, width[i], kBoxH, style.fill,
             std::string("rx='6' stroke='") + style.stroke + "' stroke-width='1.5'" +
                 (r && r->cache == "hit" ? " stroke-dasharray='5 3'" : ""));
    svg.text(x + width[i] / 2, y + 19, run.graph[i].id,
             "text-anchor='middle' font-weight='bold' font-size='13'");
    svg.text(x + width[i] / 2, y + 36, line2[i], "text-anchor='middle' font-size='11' fill='#555'");
    svg.end_group();
  }
  return svg.str();
}

std::string timeline_svg(const RunRecord& run) {
  std::vector<const NodeRun*> rows;
  for (const auto& n : run.nodes)
    if (n.status != "pending") rows.push_back(&n);
  std::stable_sort(rows.begin(), rows.end(), [](const NodeRun* a, const NodeRun* b) {
    return a->start_s != b->start_s ? a->start_s < b->start_s : a->end_s < b->end_s;
  });
  double label_w = 60;
  for (const NodeRun* r : rows) label_w = std::max(label_w, text_width(r->id, 12) + 16);
  double t_end = run.total_s;
  for (const NodeRun* r : rows) t_end = std::max(t_end, r->end_s);
  if (!(t_end > 0)) t_end = 1;
  constexpr double kPlotW = 760, kRowH = 22, kStripH = 44, kTop = 12, kRight = 70;
  const double left = label_w;
  const double strip_top = kTop, rows_top = kTop + kStripH + 16;
  const double height = rows_top + kRowH * double(rows.size()) + 40;
  Svg svg(left + kPlotW + kRight, height, 12);
  const auto X = [&](double t) { return left + kPlotW * t / t_end; };

  // Time grid and axis.
  for (double t : nice_ticks(0, t_end, 8)) {
    svg.line(X(t), strip_top, X(t), height - 28, "#e3e3e3");
    svg.text(X(t), height - 12, Svg::number(t) + " s", "text-anchor='middle' fill='#555'");
  }

  // How many nodes ran at each moment.
  std::vector<Interval> intervals;
  for (const NodeRun* r : rows) intervals.push_back({r->start_s, r->end_s});
  const auto steps = running_count(intervals);
  const int most = std::max(1, max_running(intervals));
  svg.text(left - 8, strip_top + kStripH / 2 + 4, "running", "text-anchor='end' fill='#555'");
  svg.rect(left, strip_top, kPlotW, kStripH, "#f7f9fb", "stroke='#dde3e8'");
  std::vector<std::array<double, 2>> line;
  double level = strip_top + kStripH;
  line.push_back({left, level});
  for (const auto& [t, count] : steps) {
    line.push_back({X(t), level});
    level = strip_top + kStripH - (kStripH - 6) * double(count) / double(most);
    line.push_back({X(t), level});
  }
  line.push_back({X(t_end), level});
  svg.polyline(line, "#2f6db5", 1.5);
  svg.text(left + kPlotW + 6, strip_top + 10, "max " + std::to_string(most), "fill='#2f6db5'");

  for (size_t k = 0; k < rows.size(); ++k) {
    const NodeRun& r = *rows[k];
    const double ry = rows_top + kRowH * double(k);
    if (k % 2 == 0) svg.rect(0, ry, left + kPlotW, kRowH, "#fafafa");
    svg.text(left - 8, ry + kRowH / 2 + 4, r.id, "text-anchor='end'");
    const StatusStyle style = status_style(r.status);
    const double bx = X(r.start_s), bw = std::max(2.0, X(r.end_s) - X(r.start_s));
    svg.begin_group(r.id + " (" + r.type + "): " + r.status + ", " + seconds_text(r.start_s) +
                    " \u2192 " + seconds_text(r.end_s) + " (" + seconds_text(r.wall_s) + ")" +
                    (r.cache.empty() ? "" : ", cache " + r.cache));
    svg.rect(bx, ry + 4, bw, kRowH - 8, style.stroke,
             "class='timeline-bar' rx='2'" +
                 std::string(r.cache == "hit" ? " fill-opacity='0.45'" : ""));
    svg.end_group();
    svg.text(bx + bw + 5, ry + kRowH / 2 + 4, seconds_text(r.wall_s), "fill='#555' font-size='11'");
  }
  return svg.str();
}

std::string scatter_svg(const ScatterChart& c) {
  constexpr double kLeft = 70, kTop = 16, kW = 440, kH = 280, kBottom = 56;
  const bool categorical = !c.x_categories.empty();
  double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
  for (const auto& p : c.points) {
    if (std::isnan(p.x) || std::isnan(p.y)) continue;
    const double xe = std::isnan(p.x_err) ? 0 : p.x_err, ye = std::isnan(p.y_err) ? 0 : p.y_err;
    x_lo = std::min(x_lo, p.x - xe), x_hi = std::max(x_hi, p.x + xe);
    y_lo = std::min(y_lo, p.y - ye), y_hi = std::max(y_hi, p.y + ye);
  }
  if (categorical) x_lo = -0.5, x_hi = double(c.x_categories.size()) - 0.5;
  if (!std::isfinite(x_lo)) x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;
  // A margin of 8% so that no point sits on the frame; a single value gets a range around it.
  const auto pad = [](double& lo, double& hi) {
    const double span = hi > lo ? hi - lo : std::max(std::fabs(lo), 1.0);
    lo -= 0.08 * span, hi += 0.08 * span;
  };
  if (!categorical) pad(x_lo, x_hi);
  pad(y_lo, y_hi);
  const bool legend = c.series_names.size() > 1;
  const double legend_h = legend ? 18 * double(c.series_names.size()) + 6 : 0;
  Svg svg(kLeft + kW + 20, kTop + kH + kBottom + legend_h, 12);
  const auto X = [&](double v) { return kLeft + kW * (v - x_lo) / (x_hi - x_lo); };
  const auto Y = [&](double v) { return kTop + kH * (1 - (v - y_lo) / (y_hi - y_lo)); };

  svg.rect(kLeft, kTop, kW, kH, "#fcfcfd", "stroke='#c9d1d9'");
  for (double t : nice_ticks(y_lo, y_hi, 6)) {
    svg.line(kLeft, Y(t), kLeft + kW, Y(t), "#eceff2");
    svg.text(kLeft - 6, Y(t) + 4, Svg::number(t), "text-anchor='end' fill='#555'");
  }
  if (categorical) {
    for (size_t i = 0; i < c.x_categories.size(); ++i)
      svg.text(X(double(i)), kTop + kH + 18, c.x_categories[i], "text-anchor='middle' fill='#555'");
  } else {
    for (double t : nice_ticks(x_lo, x_hi, 7)) {
      svg.line(X(t), kTop, X(t), kTop + kH, "#eceff2");
      svg.text(X(t), kTop + kH + 18, Svg::number(t), "text-anchor='middle' fill='#555'");
    }
  }
  svg.text(kLeft + kW / 2, kTop + kH + 42, c.x_label, "text-anchor='middle' font-weight='bold'");
  svg.text(16, kTop + kH / 2, c.y_label,
           "text-anchor='middle' font-weight='bold' transform='rotate(-90 16 " +
               Svg::number(kTop + kH / 2) + ")'");

  std::vector<ChartPoint> plain;
  for (const auto& p : c.points) plain.push_back({p.x, p.y});
  if (c.pareto) {
    // A step line through the front: each point holds its y until the next one improves it.
    const auto front = pareto_front(plain, c.lower_y_is_better);
    std::vector<std::array<double, 2>> steps;
    for (size_t k = 0; k < front.size(); ++k) {
      const auto& p = plain[front[k]];
      if (k) steps.push_back({X(p.x), steps.back()[1]});
      steps.push_back({X(p.x), Y(p.y)});
    }
    if (!steps.empty()) steps.push_back({kLeft + kW, steps.back()[1]});
    svg.begin_group("Pareto front: no other variant is both faster and better",
                    "class='pareto-front'");
    svg.polyline(steps, "#d62728", 1.5, "stroke-dasharray='6 4'");
    svg.end_group();
    if (!front.empty())
      svg.text(kLeft + kW, kTop + kH + 42, "- - Pareto front", "text-anchor='end' fill='#d62728'");
  }
  if (c.join_series) {
    std::map<int, std::vector<std::array<double, 2>>> lines;
    for (const auto& p : c.points)
      if (!std::isnan(p.x) && !std::isnan(p.y)) lines[p.series].push_back({X(p.x), Y(p.y)});
    for (auto& [s, pts] : lines) {
      std::sort(pts.begin(), pts.end());
      svg.polyline(pts, series_colour(s), 1.2);
    }
  }
  for (const auto& p : c.points) {
    if (std::isnan(p.x) || std::isnan(p.y)) continue;
    const std::string colour = series_colour(p.series);
    svg.begin_group(p.label, "class='chart-point'");
    if (p.y_err > 0) {
      svg.line(X(p.x), Y(p.y - p.y_err), X(p.x), Y(p.y + p.y_err), colour);
      svg.line(X(p.x) - 4, Y(p.y - p.y_err), X(p.x) + 4, Y(p.y - p.y_err), colour);
      svg.line(X(p.x) - 4, Y(p.y + p.y_err), X(p.x) + 4, Y(p.y + p.y_err), colour);
    }
    if (p.x_err > 0 && !categorical) {
      svg.line(X(p.x - p.x_err), Y(p.y), X(p.x + p.x_err), Y(p.y), colour);
      svg.line(X(p.x - p.x_err), Y(p.y) - 4, X(p.x - p.x_err), Y(p.y) + 4, colour);
      svg.line(X(p.x + p.x_err), Y(p.y) - 4, X(p.x + p.x_err), Y(p.y) + 4, colour);
    }
    svg.circle(X(p.x), Y(p.y), 4.5, colour, "stroke='white' stroke-width='1'");
    if (!p.tag.empty())
      svg.text(X(p.x) + 6, Y(p.y) - 6, p.tag,
               "font-size='11' fill='#333' stroke='white' stroke-width='3' paint-order='stroke'");
    svg.end_group();
  }
  if (legend)
    for (size_t s = 0; s < c.series_names.size(); ++s) {
      const double ly = kTop + kH + kBottom + 14 + 18 * double(s);
      svg.circle(kLeft + 6, ly - 4, 4.5, series_colour(int(s)));
      svg.text(kLeft + 16, ly, c.series_names[s], "font-size='11'");
    }
  return svg.str();
}

}  // namespace gslift::report
