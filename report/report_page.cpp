#include "report/report_page.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "base/atomic_file.hpp"
#include "base/errors.hpp"
#include "report/charts.hpp"
#include "report/floors.hpp"
#include "report/html.hpp"
#include "report/timeline.hpp"

namespace gslift::report {

namespace fs = std::filesystem;

namespace {

std::string esc(const std::string& s) {
  return html_escape(s);
}

std::string seconds(double s) {
  if (std::isnan(s)) return "–";
  char buf[32];
  std::snprintf(buf, sizeof buf, s < 10 ? "%.2f s" : "%.1f s", s);
  return buf;
}

std::string megabytes(double mb) {
  if (std::isnan(mb)) return "–";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f MB", mb);
  return buf;
}

std::string badge(const std::string& word) {
  return "<span class=\"badge " + esc(word) + "\">" + esc(word) + "</span>";
}

std::string figure(const std::string& id, const std::string& svg, const std::string& caption) {
  return "<figure class=\"chart\" id=\"" + esc(id) + "\">\n" + svg + "<figcaption>" + caption +
         "</figcaption></figure>\n";
}

// The nodes' status, times, memory and cache state, one row each, in the graph's order.
std::string node_table(const RunRecord& run) {
  const bool cache = run.has_cache_column();
  double longest = 0;
  for (const auto& n : run.nodes) longest = std::max(longest, n.wall_s);
  std::string h =
      "<div class=\"scroll\"><table class=\"node-table\">\n<tr><th>node</th><th>type</th>"
      "<th>status</th>";
  if (cache) h += "<th>cache</th>";
  h += "<th class=\"num\">start</th><th class=\"num\">end</th><th class=\"num\">wall</th><th></th>"
       "<th class=\"num\">peak RSS</th><th>error</th></tr>\n";
  for (const auto& n : run.nodes) {
    const bool ran = n.status != "pending";
    h += std::string("<tr") + (n.status == "failed" ? " class=\"failed\"" : "") + "><td><code>" +
         esc(n.id) + "</code></td><td><code>" + esc(n.type) + "</code></td><td>" + badge(n.status) +
         "</td>";
    if (cache) h += "<td>" + (n.cache.empty() ? std::string("–") : badge(n.cache)) + "</td>";
    const double share = longest > 0 ? 120 * n.wall_s / longest : 0;
    h += "<td class=\"num\">" + (ran ? seconds(n.start_s) : "–") + "</td><td class=\"num\">" +
         (ran ? seconds(n.end_s) : "–") + "</td><td class=\"num\">" +
         (ran ? seconds(n.wall_s) : "–") +
         "</td><td><span class=\"bar\" style=\"width:" + number_text(std::round(share)) +
         "px\"></span></td><td class=\"num\">" + (ran ? megabytes(n.peak_rss_mb) : "–") +
         "</td><td>" + esc(n.error) + "</td></tr>\n";
  }
  return h + "</table></div>\n";
}

std::string records_section(const RunRecord& run) {
  std::string cards;
  for (const auto& n : run.nodes) {
    if (n.records.empty()) continue;
    cards += "<div class=\"records\" id=\"records-" + esc(n.id) + "\"><h3><code>" + esc(n.id) +
             "</code> <span class=\"note\">" + esc(n.type) + "</span></h3><table>\n";
    for (const auto& [key, value] : n.records)
      cards += "<tr><td>" + esc(key) + "</td><td class=\"num\">" + esc(value_text(value)) +
               "</td></tr>\n";
    cards += "</table></div>\n";
  }
  if (cards.empty()) return {};
  return "<section id=\"records\"><h2>Records</h2><p class=\"note\">What each node recorded "
         "(counts, losses, metrics).</p><div class=\"cards\">\n" +
         cards + "</div></section>\n";
}

std::string params_section(const RunRecord& run) {
  std::string h = "<section id=\"params\"><h2>Params</h2>";
  if (!run.graph_params.empty()) {
    h += "<p>graph params: ";
    for (const auto& [k, v] : run.graph_params)
      h += "<code>" + esc(k) + "=" + esc(value_text(v)) + "</code> ";
    h += "</p>";
  }
  for (const auto& g : run.graph) {
    h += "<details><summary><code>" + esc(g.id) + "</code> <span class=\"note\">" + esc(g.type) +
         (g.loc.empty() ? "" : " · " + esc(g.loc)) + "</span></summary><table>\n";
    for (const auto& [port, ref] : g.inputs)
      h += "<tr><td>input <code>" + esc(port) + "</code></td><td><code>" + esc(ref) +
           "</code></td></tr>\n";
    for (const auto& [k, v] : g.params)
      h += "<tr><td><code>" + esc(k) + "</code></td><td><code>" + esc(value_text(v)) +
           "</code></td></tr>\n";
    h += "</table></details>\n";
  }
  return h + "</section>\n";
}

// The files a run wrote, grouped by the top folder (the node that wrote them), in the graph's
// order; the run's own run.json and report.html are not among them.
std::vector<std::pair<std::string, std::vector<fs::path>>> run_files(const RunRecord& run) {
  std::map<std::string, std::vector<fs::path>> by_folder;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(run.dir, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    const fs::path rel = fs::relative(it->path(), run.dir, ec);
    if (rel.begin() == rel.end() || std::next(rel.begin()) == rel.end()) continue;  // top level
    by_folder[rel.begin()->string()].push_back(rel);
  }
  std::vector<std::pair<std::string, std::vector<fs::path>>> out;
  for (const auto& g : run.graph) {
    auto it = by_folder.find(g.id);
    if (it == by_folder.end()) continue;
    out.push_back(*it);
    by_folder.erase(it);
  }
  for (auto& entry : by_folder) out.push_back(entry);
  for (auto& [folder, files] : out) std::sort(files.begin(), files.end());
  return out;
}

// The side-by-side picture of a view (ground truth | render | instances), as the text-query node
// names it (nodes/inference/query_files.hpp kGtRenderInstancesSuffix): the report shows these
// first, under the results, and not again among the pictures.
bool is_side_by_side(const fs::path& rel) {
  const std::string suffix = "_gt_render_instances.png", name = rel.filename().string();
  return name.size() > suffix.size() &&
         name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A picture of the run folder (`data`: the bytes of its file `rel`) as an <img>: embedded as a
// data URI, or linked to the file.
std::string picture_img(const fs::path& rel, const std::string& data, bool embed) {
  const PixelSize px = picture_size(data);
  const std::string src =
      embed ? "data:" + picture_mime(rel) + ";base64," + base64(data) : esc(relative_href(rel));
  return "<img src=\"" + src + "\" alt=\"" + esc(rel.generic_string()) + "\"" +
         (px.width ? " width=\"" + std::to_string(px.width) + "\" height=\"" +
                         std::to_string(px.height) + "\""
                   : std::string()) +
         " loading=\"eager\">";
}

// What the run measured, first: the headline metrics beside the README's floors (floors.hpp),
// each evaluation node's table as its metrics.md has it, then ground truth | render | instances
// for every view that has that picture.
std::string results_section(const RunRecord& run, const ReportOptions& options,
                            ReportStats* stats) {
  std::string h = "<section id=\"results\"><h2>Results</h2>\n";
  if (run.headline.empty()) {
    h += "<p class=\"note\">No evaluation node recorded a metric in this run.</p>\n";
  } else {
    h += "<table class=\"headline\">\n<tr><th>metric</th><th class=\"num\">value</th>"
         "<th class=\"num\">floor</th><th></th><th>floor set by</th></tr>\n";
    for (const auto& [metric, value] : run.headline) {
      const MetricFloor* f = find_floor(run.graph_name, metric);
      h += "<tr><td><code>" + esc(metric) + "</code></td><td class=\"num headline-value\">" +
           esc(number_text(value)) + "</td><td class=\"num\">" +
           (f ? "&ge; " + esc(number_text(f->floor)) : std::string("–")) + "</td><td>" +
           (f ? badge(value >= f->floor ? "holds" : "below") : std::string()) + "</td><td>" +
           (f ? esc(f->source) : std::string()) + "</td></tr>\n";
    }
    h += "</table>\n<p class=\"note\">The floors are what the README's Results holds the method "
         "to, over the mean of its dev rooms (report/floors.cpp); one room may sit below "
         "them.</p>\n";
  }
  for (const auto& n : run.nodes) {
    if (n.type.rfind("eval.", 0) != 0) continue;
    std::error_code ec;
    const fs::path md = run.dir / n.id / "metrics.md";
    if (!fs::is_regular_file(md, ec)) continue;
    const std::string table = markdown_table_html(read_bytes(md));
    if (!table.empty())
      h += "<h3 id=\"classes-" + esc(n.id) + "\">Per class: <code>" + esc(n.id) +
           "/metrics.md</code></h3><div class=\"scroll\">" + table + "</div>\n";
  }
  std::string views;
  for (const auto& [folder, files] : run_files(run))
    for (const fs::path& rel : files) {
      if (!is_side_by_side(rel)) continue;
      views += "<figure class=\"side-by-side\">" +
               picture_img(rel, read_bytes(run.dir / rel), options.embed_pictures) +
               "<figcaption>ground truth | render | instances · <code>" +
               esc(rel.generic_string()) + "</code></figcaption></figure>\n";
      if (stats) ++(options.embed_pictures ? stats->pictures_embedded : stats->pictures_linked);
    }
  if (!views.empty()) h += "<h3 id=\"views\">Ground truth | render | instances</h3>\n" + views;
  return h + "</section>\n";
}

std::string pictures_and_files(const RunRecord& run, const ReportOptions& options,
                               ReportStats* stats) {
  std::string pictures, others, skipped;
  uintmax_t used = 0;
  size_t shown = 0, skipped_count = 0;
  for (const auto& [folder, files] : run_files(run)) {
    std::string group;
    for (const fs::path& rel : files) {
      std::error_code ec;
      const uintmax_t bytes = fs::file_size(run.dir / rel, ec);
      const std::string link = "<a href=\"" + esc(relative_href(rel)) + "\"><code>" +
                               esc(rel.generic_string()) + "</code></a>";
      const std::string mime = picture_mime(rel);
      if (is_side_by_side(rel)) continue;  // shown under the results
      if (mime.empty()) {
        others += "<tr><td>" + link + "</td><td class=\"num\">" + size_text(bytes) + "</td></tr>\n";
        continue;
      }
      if (options.embed_pictures && used + bytes > options.max_picture_bytes) {
        skipped += "<li>" + link + " (" + size_text(bytes) + ")</li>\n";
        ++skipped_count;
        continue;
      }
      const std::string data = read_bytes(run.dir / rel);
      const PixelSize px = picture_size(data);
      const std::string dims = px.width ? std::to_string(px.width) + "×" + std::to_string(px.height)
                                        : std::string("size unknown");
      if (options.embed_pictures) used += data.size();
      ++shown;
      group += "<figure class=\"picture\">" + picture_img(rel, data, options.embed_pictures) +
               "<figcaption>" + link + " · " + dims + " · " + size_text(bytes) +
               "</figcaption></figure>\n";
    }
    if (!group.empty())
      pictures += "<h3><code>" + esc(folder) + "</code></h3><div class=\"pictures\">\n" + group +
                  "</div>\n";
  }
  if (stats) {
    (options.embed_pictures ? stats->pictures_embedded : stats->pictures_linked) += shown;
    stats->pictures_skipped += skipped_count;
  }
  std::string h;
  if (!pictures.empty() || !skipped.empty()) {
    const std::string count = std::to_string(shown) + " picture" + (shown == 1 ? "" : "s");
    h += "<section id=\"pictures\"><h2>Pictures</h2><p class=\"note\">" +
         (options.embed_pictures
              ? count + " embedded at full resolution (" + size_text(used) +
                    "); the links open the files beside this page."
              : count +
                    " shown from the files beside this page, not embedded (this page "
                    "belongs to a sweep's report; gslift report on this folder embeds them).") +
         "</p>\n" + pictures;
    if (!skipped.empty())
      h += "<p class=\"note skipped\">" + std::to_string(skipped_count) +
           " more not embedded: the embedded pictures reached the cap of " +
           size_text(options.max_picture_bytes) +
           " (gslift report --max-picture-mb raises it):</p><ul>\n" + skipped + "</ul>\n";
    h += "</section>\n";
  }
  if (!others.empty())
    h += "<section id=\"files\"><h2>Other files</h2><table>\n" + others + "</table></section>\n";
  return h;
}

std::string params_text(const std::map<std::string, std::string>& params) {
  std::string t;
  for (const auto& [k, v] : params) t += (t.empty() ? "" : ", ") + k + "=" + v;
  return t.empty() ? "(defaults)" : t;
}

std::string mean_std_text(const MeanStd& m, const std::string& unit = {}) {
  if (std::isnan(m.mean)) return "–";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g ± %.2g%s", m.mean, std::isnan(m.std) ? 0.0 : m.std,
                unit.c_str());
  return buf;
}

}  // namespace

bool lower_is_better(const std::string& metric) {
  const std::string key = metric.substr(metric.find('.') + 1);
  for (const char* word : {"loss", "error", "rmse", "mae", "seconds", "bytes", "time"})
    if (key.find(word) != std::string::npos) return true;
  return key.size() > 2 && key.compare(key.size() - 2, 2, "_s") == 0;
}

std::string run_report_html(const RunRecord& run, const ReportOptions& options,
                            ReportStats* stats) {
  std::string b = "<h1>" + esc(run.graph_name) + " " + badge(run.status) + "</h1>\n";
  b += "<p class=\"meta\"><span>run folder <code>" + esc(run.dir.string()) +
       "</code></span><span>started " + esc(run.started_at) + "</span><span>total " +
       seconds(run.total_s) + "</span><span>peak RSS " + megabytes(run.peak_rss_mb) +
       "</span><span>seed " + std::to_string(run.seed) + "</span><span>threads " +
       std::to_string(run.threads) + "</span><span>gslift " + esc(run.version) + " (" +
       esc(run.git) + ")</span></p>\n";
  if (!run.graph_files.empty()) {
    b += "<p class=\"meta\">graph files:";
    for (const auto& f : run.graph_files) b += " <code>" + esc(f) + "</code>";
    b += "</p>\n";
  }
  if (!run.error.empty()) b += "<h3>Error</h3><div class=\"error\">" + esc(run.error) + "</div>\n";
  for (const auto& n : run.nodes)
    if (!n.error.empty() && run.error.find(n.error) == std::string::npos)
      b += "<div class=\"error\">node " + esc(n.id) + ": " + esc(n.error) + "</div>\n";

  b += results_section(run, options, stats);
  b += "<section id=\"graph\"><h2>Graph</h2>" +
       figure("graph-diagram", graph_diagram_svg(run),
              "The resolved graph, sources on top; arrows are inputs labelled by port. Box "
              "colour: green ok, red failed, grey not run; a dashed border is a cache hit.") +
       "</section>\n";
  std::vector<Interval> intervals;
  for (const auto& n : run.nodes)
    if (n.status != "pending") intervals.push_back({n.start_s, n.end_s});
  b += "<section id=\"timeline\"><h2>Timeline</h2>" +
       figure("timeline-chart", timeline_svg(run),
              "Each node's run on the flow graph's clock (seconds since the run started); bars "
              "that overlap in time ran concurrently (the strip on top counts them; at most " +
                  std::to_string(max_running(intervals)) +
                  " nodes ran at once). Pale bars are cache hits.") +
       "</section>\n";
  b += "<section id=\"nodes\"><h2>Nodes: time and memory</h2>" + node_table(run) +
       "<p class=\"note\">peak RSS: the process's peak resident memory when the node ended.</p>"
       "</section>\n";
  b += records_section(run);
  b += pictures_and_files(run, options, stats);
  b += params_section(run);
  return html_page("gslift report: " + run.graph_name, b);
}

std::string sweep_report_html(const SweepRecord& sweep) {
  // The varied params: the grid's, else every param a run names.
  std::vector<std::string> varied;
  for (const auto& [name, values] : sweep.grid) varied.push_back(name);
  if (varied.empty()) {
    std::set<std::string> names;
    for (const auto& r : sweep.runs)
      for (const auto& [k, v] : r.params) names.insert(k);
    varied.assign(names.begin(), names.end());
  }
  // The summary's columns and the charts are for the headline metrics: a LangOR sweep records
  // some 80 metrics per run (losses, per-class IoU), and the rest go to a folded table. A sweep
  // without headline metrics shows them all.
  std::set<std::string> metric_set;
  for (const auto& g : sweep.summary)
    for (const auto& [k, v] : g.metrics) metric_set.insert(k);
  const std::vector<std::string> all_metrics(metric_set.begin(), metric_set.end());
  std::vector<std::string> metrics;
  for (const auto& m : sweep.headline)
    if (metric_set.count(m)) metrics.push_back(m);
  if (metrics.empty()) metrics = all_metrics;
  size_t failed = 0;
  for (const auto& r : sweep.runs) failed += r.status != "ok";
  // Each run's record (absent for a run that failed before writing one), and the grid points
  // with a run that loaded nodes from the stage cache: their time is a cache read, not the time
  // to compute, so the charts tag them instead of presenting them as fast.
  std::vector<std::optional<RunRecord>> records;
  std::vector<std::string> no_record;  // why a run has none
  std::set<std::map<std::string, std::string>> cached_params;
  for (const auto& r : sweep.runs) {
    try {
      records.emplace_back(read_run_record(sweep.dir / r.dir));
      no_record.emplace_back();
      if (records.back()->cache_hits()) cached_params.insert(r.params);
    } catch (const InputError& e) {
      records.emplace_back(std::nullopt);
      no_record.emplace_back(e.what());
    }
  }

  const std::string status =
      failed ? "<span class=\"badge failed\">" + std::to_string(failed) + " failed</span>"
             : badge("ok");
  std::string b = "<h1>Sweep: " + esc(sweep.graph) + " " + status +
                  "</h1>\n<p class=\"meta\"><span>sweep folder <code>" + esc(sweep.dir.string()) +
                  "</code></span><span>" + std::to_string(sweep.runs.size()) +
                  " runs</span><span>" + std::to_string(failed) + " failed</span><span>seeds";
  for (uint64_t s : sweep.seeds) b += " " + std::to_string(s);
  b += "</span></p>\n<p class=\"meta\">grid:";
  for (const auto& [name, values] : sweep.grid) {
    b += " <code>" + esc(name) + " = ";
    for (size_t i = 0; i < values.size(); ++i) b += (i ? ", " : "") + esc(values[i]);
    b += "</code>";
  }
  b += "</p>\n";

  // Summary: one row per grid point, mean ± std over seeds.
  b += "<section id=\"summary\"><h2>Summary (mean ± std over seeds)</h2><div class=\"scroll\">"
       "<table class=\"summary-table\">\n<tr><th class=\"num\">#</th>";
  for (const auto& p : varied) b += "<th>" + esc(p) + "</th>";
  b += "<th class=\"num\">ok</th><th class=\"num\">failed</th>";
  for (const auto& m : metrics) b += "<th class=\"num\">" + esc(m) + "</th>";
  b += "<th class=\"num\">total</th><th class=\"num\">peak RSS</th></tr>\n";
  for (size_t k = 0; k < sweep.summary.size(); ++k) {
    const SweepGroup& g = sweep.summary[k];
    b += std::string("<tr") + (g.failed ? " class=\"failed\"" : "") + "><td class=\"num\">" +
         std::to_string(k + 1) + "</td>";
    for (const auto& p : varied) {
      auto it = g.params.find(p);
      b += "<td><code>" + esc(it == g.params.end() ? "" : it->second) + "</code></td>";
    }
    b += "<td class=\"num\">" + std::to_string(g.n) + "</td><td class=\"num\">" +
         std::to_string(g.failed) + "</td>";
    for (const auto& m : metrics) {
      auto it = g.metrics.find(m);
      b += "<td class=\"num\">" + (it == g.metrics.end() ? "–" : mean_std_text(it->second)) +
           "</td>";
    }
    b += "<td class=\"num\">" + mean_std_text(g.total_s, " s") + "</td><td class=\"num\">" +
         mean_std_text(g.peak_rss_mb, " MB") + "</td></tr>\n";
  }
  b += "</table></div>\n";
  if (metrics.size() < all_metrics.size()) {
    // Every metric, a row each, a column per grid point.
    b += "<details id=\"all-metrics\"><summary>All " + std::to_string(all_metrics.size()) +
         " metrics (mean ± std; columns: the rows above)</summary><div class=\"scroll\"><table>"
         "\n<tr><th>metric</th>";
    for (size_t k = 0; k < sweep.summary.size(); ++k)
      b += "<th class=\"num\">#" + std::to_string(k + 1) + "</th>";
    b += "</tr>\n";
    for (const auto& m : all_metrics) {
      b += "<tr><td>" + esc(m) + "</td>";
      for (const auto& g : sweep.summary) {
        auto it = g.metrics.find(m);
        b += "<td class=\"num\">" + (it == g.metrics.end() ? "–" : mean_std_text(it->second)) +
             "</td>";
      }
      b += "</tr>\n";
    }
    b += "</table></div></details>\n";
  }
  b += "</section>\n";

  // Charts: each metric against time and memory (Pareto front), and against each varied param.
  std::string charts;
  int chart_id = 0;
  for (const auto& m : metrics) {
    const bool lower = lower_is_better(m);
    for (const char* axis : {"total_s", "peak_rss_mb"}) {
      ScatterChart c;
      const bool time = std::string(axis) == "total_s";
      c.x_label = time ? "wall time of the run (s)" : "peak RSS (MB)";
      c.y_label = m;
      c.pareto = true;
      c.lower_y_is_better = lower;
      for (size_t k = 0; k < sweep.summary.size(); ++k) {
        const SweepGroup& g = sweep.summary[k];
        auto it = g.metrics.find(m);
        if (it == g.metrics.end()) continue;
        const MeanStd& x = time ? g.total_s : g.peak_rss_mb;
        const bool cached = time && cached_params.count(g.params);
        c.points.push_back({x.mean, x.std, it->second.mean, it->second.std,
                            "#" + std::to_string(k + 1) + " " + params_text(g.params) + "\n" + m +
                                " " + mean_std_text(it->second) + "\n" + c.x_label + " " +
                                mean_std_text(x) +
                                (cached ? " (stage cache: not compute time)" : ""),
                            "#" + std::to_string(k + 1) + (cached ? " cached" : ""), 0});
      }
      charts += figure("chart-" + std::to_string(chart_id++), scatter_svg(c),
                       esc(m) + " against " + esc(c.x_label) + "; error bars: ± one std over " +
                           "seeds; #: the row in the summary; dashed: Pareto front (" +
                           (lower ? "lower" : "higher") + " is better)." +
                           (time && !cached_params.empty()
                                ? " Points tagged <em>cached</em> have a run that loaded nodes "
                                  "from the stage cache: their time is not the time to compute "
                                  "them (gslift sweep --no-cache measures it)."
                                : std::string()));
    }
    for (const auto& p : varied) {
      ScatterChart c;
      c.x_label = p;
      c.y_label = m;
      c.join_series = true;
      auto grid = sweep.grid.find(p);
      if (grid != sweep.grid.end()) c.x_categories = grid->second;
      std::map<std::string, int> series;
      for (const auto& g : sweep.summary) {
        auto it = g.metrics.find(m);
        auto value = g.params.find(p);
        if (it == g.metrics.end() || value == g.params.end()) continue;
        auto at = std::find(c.x_categories.begin(), c.x_categories.end(), value->second);
        if (at == c.x_categories.end()) {
          c.x_categories.push_back(value->second);
          at = c.x_categories.end() - 1;
        }
        std::map<std::string, std::string> others = g.params;
        others.erase(p);
        const std::string name = params_text(others);
        const auto s = series.emplace(name, int(series.size())).first->second;
        if (size_t(s) == c.series_names.size()) c.series_names.push_back(name);
        c.points.push_back({double(at - c.x_categories.begin()), 0, it->second.mean, it->second.std,
                            params_text(g.params) + "\n" + m + " " + mean_std_text(it->second), "",
                            s});
      }
      if (c.x_categories.size() < 2) continue;
      charts += figure("chart-" + std::to_string(chart_id++), scatter_svg(c),
                       esc(m) + " against " + esc(p) + "; one line per setting of the other " +
                           "params; error bars: ± one std over seeds.");
    }
  }
  if (!charts.empty())
    b += "<section id=\"charts\"><h2>Charts</h2><div class=\"charts\">\n" + charts +
         "</div></section>\n";

  // Runs: a row each, then a section each with its nodes' times.
  b += "<section id=\"runs\"><h2>Runs</h2><div class=\"scroll\"><table class=\"runs-table\">\n"
       "<tr><th>run</th><th class=\"num\">seed</th><th>params</th><th>status</th>"
       "<th class=\"num\">total</th><th>cache</th><th class=\"num\">peak RSS</th>";
  for (const auto& m : metrics) b += "<th class=\"num\">" + esc(m) + "</th>";
  b += "<th>error</th></tr>\n";
  std::string sections;
  for (size_t i = 0; i < sweep.runs.size(); ++i) {
    const SweepRun& r = sweep.runs[i];
    const std::optional<RunRecord>& run = records[i];
    const std::string anchor = "run-" + fs::path(r.dir).filename().string();
    b += std::string("<tr") + (r.status != "ok" ? " class=\"failed\"" : "") + "><td><a href=\"#" +
         esc(anchor) + "\"><code>" + esc(r.dir) + "</code></a></td><td class=\"num\">" +
         std::to_string(r.seed) + "</td><td><code>" + esc(params_text(r.params)) +
         "</code></td><td>" + badge(r.status) + "</td><td class=\"num\">" + seconds(r.total_s) +
         "</td><td>" +
         (run && run->cache_hits()
              ? badge("cached") + " <span class=\"note\">" + std::to_string(run->cache_hits()) +
                    " of " + std::to_string(run->nodes.size()) + " nodes</span>"
              : std::string("–")) +
         "</td><td class=\"num\">" + megabytes(r.peak_rss_mb) + "</td>";
    for (const auto& m : metrics) {
      auto it = r.metrics.find(m);
      b += "<td class=\"num\">" + (it == r.metrics.end() ? "–" : number_text(it->second)) + "</td>";
    }
    b += "<td>" + esc(r.error) + "</td></tr>\n";

    sections += "<details id=\"" + esc(anchor) + "\"><summary><code>" + esc(r.dir) + "</code> " +
                badge(r.status) + " <span class=\"note\">seed " + std::to_string(r.seed) + " · " +
                esc(params_text(r.params)) + "</span></summary>";
    if (run) {
      sections += "<p><a href=\"" + esc(relative_href(fs::path(r.dir) / "report.html")) +
                  "\">the run's own report</a> (graph, timeline, pictures)</p>" + node_table(*run);
      if (!run->error.empty()) sections += "<div class=\"error\">" + esc(run->error) + "</div>";
    } else {
      sections += "<p class=\"note\">no run record: " + esc(no_record[i]) + "</p>";
    }
    if (!r.error.empty()) sections += "<div class=\"error\">" + esc(r.error) + "</div>";
    sections += "</details>\n";
  }
  b += "</table></div>\n<h3>Each run</h3>\n" + sections + "</section>\n";
  return html_page("gslift sweep report: " + sweep.graph, b);
}

fs::path write_report(const fs::path& dir, const ReportOptions& options, ReportStats* stats) {
  const fs::path page = dir / "report.html";
  if (is_sweep_dir(dir)) {
    const SweepRecord sweep = read_sweep_record(dir);
    ReportOptions linked = options;
    linked.embed_pictures = false;
    for (const auto& r : sweep.runs) {
      try {
        const RunRecord run = read_run_record(dir / r.dir);
        write_file_atomically(dir / r.dir / "report.html", run_report_html(run, linked, stats));
        if (stats) ++stats->runs;
      } catch (const InputError&) {
        // A run that left no record (it failed before writing one): its row says so.
      }
    }
    write_file_atomically(page, sweep_report_html(sweep));
  } else {
    write_file_atomically(page, run_report_html(read_run_record(dir), options, stats));
  }
  return page;
}

}  // namespace gslift::report
