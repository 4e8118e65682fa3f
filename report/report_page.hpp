// `gslift report`: one self-contained report.html for a run folder (graph diagram, timeline, node
// times and memory, records, every picture the run wrote) or a sweep folder (summary table, the
// speed-accuracy and per-param charts, one section per run). docs/cli.md "gslift report".
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "report/records.hpp"

namespace gslift::report {

struct ReportOptions {
  // Pictures are embedded at full size (base64, about 4/3 of the file) in the order the graph ran
  // until their files add up to this; the rest are listed as skipped, with a link to the file.
  uintmax_t max_picture_bytes = uintmax_t{32} << 20;
  // False: pictures are shown from their files beside the page (relative links) instead of being
  // embedded. The run pages of a sweep do this: a sweep's runs would otherwise hold every
  // picture twice, and those pages live in the run folders anyway.
  bool embed_pictures = true;
};

struct ReportStats {
  size_t pictures_embedded = 0, pictures_skipped = 0, pictures_linked = 0;
  size_t runs = 0;  // sweeps: run reports written
};

// The page for a run folder. The picture files are read from run.dir.
std::string run_report_html(const RunRecord& run, const ReportOptions& options,
                            ReportStats* stats = nullptr);

// The page for a sweep folder; each run's section links to RUN/report.html.
std::string sweep_report_html(const SweepRecord& sweep);

// Reads DIR (a sweep when it holds sweep.json, else a run), writes DIR/report.html (for a sweep
// also each run's report.html, its pictures linked) and returns the page's path. Throws InputError
// naming the path when DIR is not a readable run or sweep folder.
std::filesystem::path write_report(const std::filesystem::path& dir, const ReportOptions& options,
                                   ReportStats* stats = nullptr);

// Whether a lower value of the metric is better (losses, errors, times, sizes), from its name:
// the Pareto front of a chart then looks for small values.
bool lower_is_better(const std::string& metric);

}  // namespace gslift::report
