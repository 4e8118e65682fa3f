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
  // The capture of an --inputs set (a room); empty without one. Rooms, like seeds, are
  // replicates: the summary pools them, and variants are compared room by room.
  std::string input;
};
// The most runs one sweep plans: each is a child process and a folder, and the plan is held in
// memory (10^6 grid points took 5.5 GB before the first run). Far above any sweep that ends.
constexpr size_t kMaxSweepRuns = 10000;

// The product of the axes' values (the first axis varies slowest), each with every input of a
// set (none: {""}) and every seed. Throws std::invalid_argument for a param on two axes (the
// later one replaced the earlier silently) and for more than kMaxSweepRuns runs, before planning
// any.
std::vector<SweepPoint> sweep_points(const std::vector<GridAxis>& axes,
                                     const std::vector<uint64_t>& seeds,
                                     const std::vector<std::string>& inputs = {""});

// A point's params as the --set texts of its run, every stage swap ("NODE.type=...") before the
// params: a later type replaces the node's earlier params, so a grid over `prompt.type` and
// `prompt.tau` runs each type at each tau instead of dropping tau (params sort by name).
std::vector<std::string> sweep_point_sets(const SweepPoint& point);

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

// sweep.json: {graph, grid, seeds, inputs, runs: [...], summary: [{params, n, failed, metrics:
// {key: {mean, std}}, total_s, peak_rss_mb, paired}]}; the summary groups runs by params, over
// seeds and inputs (failed runs are counted, not averaged). std is the sample standard deviation
// (0 for one run). Every group after the first has `paired`: {against: the first group's params,
// metrics: {key: {n, mean, low, high}}}, the mean of its differences to the first group over the
// (input, seed) pairs where both runs succeeded, with a 95% t interval (null below two pairs):
// the per-room comparison a variant is judged by (bench/README.md, "Dev and test").
nlohmann::json sweep_json(const std::string& graph, const std::vector<GridAxis>& axes,
                          const std::vector<uint64_t>& seeds, const std::vector<SweepRun>& runs,
                          const std::vector<std::string>& inputs = {});

// results.csv: a row per run (run, seed, [input,] status, error, each varied param, total_s,
// peak_rss_mb, every metric, wall_s.<node>); summary.csv: a row per params with mean and std
// columns.
std::string sweep_runs_csv(const std::vector<GridAxis>& axes, const std::vector<SweepRun>& runs);
std::string sweep_summary_csv(const std::vector<GridAxis>& axes, const nlohmann::json& sweep);

// The printed table: one line per params with the runs that succeeded and the headline metrics
// (the records of evaluation nodes, without per-class entries) as mean +- std; below it, each
// later group's paired difference to the first, mean [95% interval], for the headline metrics.
std::string sweep_table(const std::vector<GridAxis>& axes, const nlohmann::json& sweep,
                        const std::vector<std::string>& headline);

}  // namespace gslift
