// `gslift sweep`: a graph over the cartesian product of param values and seeds (the multirun of
// config tools such as Hydra), each run a `gslift run` child process in its own folder (so its
// peak memory and any crash are its own) through the stage cache, and one results table with mean
// +- std over seeds. The pieces here are plain functions over text and JSON; cli.cpp runs them.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gslift {

// One --grid: "recon.iterations=100,250,500" (NODE.PARAM or a graph param NAME; NODE.type swaps a
// stage). Commas inside [] or quotes belong to the value: "lift.x=[1,2],[3,4]" is two values.
struct GridAxis {
  std::string param;
  std::vector<std::string> values;
};
// Throws std::invalid_argument naming what is wrong.
GridAxis parse_grid(const std::string& text);

// "0-4", "0,2,7" or "3". Throws std::invalid_argument.
std::vector<uint64_t> parse_seeds(const std::string& text);

struct SweepPoint {
  std::map<std::string, std::string> params;  // param -> value, one per axis
  uint64_t seed = 0;
};
// The most runs one sweep plans: each is a child process and a folder, and the plan is held in
// memory (10^6 grid points took 5.5 GB before the first run). Far above any sweep that ends.
constexpr size_t kMaxSweepRuns = 10000;

// The product of the axes' values (the first axis varies slowest), each with every seed.
// Throws std::invalid_argument for a param on two axes (the later one replaced the earlier
// silently) and for more than kMaxSweepRuns runs, before planning any.
std::vector<SweepPoint> sweep_points(const std::vector<GridAxis>& axes,
                                     const std::vector<uint64_t>& seeds);

struct SweepRun {
  std::string dir;  // relative to the sweep folder: "runs/0003"
  SweepPoint point;
  std::string status;  // "ok", "failed", "interrupted"
  std::string error;   // empty when ok
  double total_s = 0;
  double peak_rss_mb = 0;
  std::map<std::string, double> metrics;      // "node.record" for every numeric record
  std::map<std::string, double> node_wall_s;  // node id -> its wall time
};

// A run's row from its run.json (status, error, time, memory, numeric records, node times).
SweepRun sweep_run_from_record(const nlohmann::json& run_json, SweepRun run);

// sweep.json: {graph, grid, seeds, runs: [...], summary: [{params, n, failed, metrics: {key:
// {mean, std}}, total_s, peak_rss_mb}]}; the summary groups runs by params, over seeds (failed
// runs are counted, not averaged). std is the sample standard deviation (0 for one run).
nlohmann::json sweep_json(const std::string& graph, const std::vector<GridAxis>& axes,
                          const std::vector<uint64_t>& seeds, const std::vector<SweepRun>& runs);

// results.csv: a row per run (run, seed, status, error, each varied param, total_s, peak_rss_mb,
// every metric, wall_s.<node>); summary.csv: a row per params with mean and std columns.
std::string sweep_runs_csv(const std::vector<GridAxis>& axes, const std::vector<SweepRun>& runs);
std::string sweep_summary_csv(const std::vector<GridAxis>& axes, const nlohmann::json& sweep);

// The printed table: one line per params with the runs that succeeded and the headline metrics
// (the records of evaluation nodes, without per-class entries) as mean +- std.
std::string sweep_table(const std::vector<GridAxis>& axes, const nlohmann::json& sweep,
                        const std::vector<std::string>& headline);

}  // namespace gslift
