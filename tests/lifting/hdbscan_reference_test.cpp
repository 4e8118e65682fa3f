// Our HDBSCAN against Python hdbscan 0.8.33 (algorithm "generic") on the 22 reference runs of
// ../shared/data/hdbscan_reference (README there): identical partitions on the runs flagged
// robust_to_tie_breaking, adjusted Rand index >= 0.95 on the others, and membership
// probabilities equal to the reference's on the robust runs.
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "nodes/lifting/cluster_agreement.hpp"
#include "nodes/lifting/hdbscan.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

std::vector<std::vector<double>> read_csv_rows(const std::filesystem::path& path,
                                               bool skip_header) {
  std::ifstream in(path);
  REQUIRE(in);
  std::vector<std::vector<double>> rows;
  std::string text;
  if (skip_header) std::getline(in, text);
  while (std::getline(in, text)) {
    if (text.empty()) continue;
    std::vector<double> row;
    std::istringstream fields(text);
    std::string field;
    while (std::getline(fields, field, ',')) row.push_back(std::stod(field));
    rows.push_back(std::move(row));
  }
  return rows;
}

PointMatrix to_points(const std::vector<std::vector<double>>& rows) {
  PointMatrix p(rows.size(), rows.front().size());
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t j = 0; j < rows[i].size(); ++j) p(i, j) = rows[i][j];
  return p;
}

}  // namespace

TEST_CASE("HDBSCAN matches the Python hdbscan reference runs") {
  GSLIFT_REQUIRE_SHARED_DATA("hdbscan_reference");
  const auto root = test::shared_data("hdbscan_reference");
  std::ifstream summary_file(root / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  REQUIRE(summary["runs"].size() == 22);

  std::map<std::string, PointMatrix> datasets;
  const std::regex name(R"(labels/(\w+?)__mcs(\d+)_ms(\d+|default)_(eom|leaf)(_refimpl)?\.csv)");
  int robust = 0;
  for (const auto& run : summary["runs"]) {
    const std::string file = run["file"];
    std::smatch m;
    REQUIRE(std::regex_match(file, m, name));
    const std::string dataset = m[1];
    HdbscanParams params;
    params.min_cluster_size = std::stoi(m[2]);
    params.min_samples = m[3] == "default" ? 0 : std::stoi(m[3]);
    params.selection = parse_cluster_selection(m[4]);
    params.match_reference_implementation = m[5].matched;
    // The file name and the recorded parameters must agree.
    REQUIRE(run["min_cluster_size"] == params.min_cluster_size);
    REQUIRE(run["match_reference_implementation"] == params.match_reference_implementation);

    if (!datasets.count(dataset))
      datasets[dataset] = to_points(read_csv_rows(root / (dataset + "_X.csv"), false));
    const PointMatrix& points = datasets[dataset];
    const auto reference = read_csv_rows(root / file, true);
    REQUIRE(reference.size() == static_cast<size_t>(points.rows()));
    std::vector<int> ref_labels;
    for (const auto& row : reference) ref_labels.push_back(static_cast<int>(row[0]));

    const HdbscanResult ours = hdbscan(points, params);
    const double ari = adjusted_rand_index(ours.labels, ref_labels);
    const bool is_robust = run["robust_to_tie_breaking"];
    INFO(file << ": " << ours.clusters << " clusters (reference " << run["n_clusters"] << "), ARI "
              << ari);
    double max_prob_diff = 0;
    for (size_t i = 0; i < reference.size(); ++i)
      max_prob_diff = std::max(max_prob_diff, std::abs(ours.probabilities[i] - reference[i][1]));
    INFO("max |probability - reference| = " << max_prob_diff);
    if (is_robust) {
      ++robust;
      CHECK(same_partition(ours.labels, ref_labels));
      CHECK(max_prob_diff < 1e-6);
    } else {
      CHECK(ari >= 0.95);
    }
    WARN(file << (is_robust ? " [robust]" : "") << ": clusters " << ours.clusters << "/"
              << run["n_clusters"] << ", ARI " << ari << ", identical "
              << same_partition(ours.labels, ref_labels) << ", max prob diff " << max_prob_diff);
  }
  CHECK(robust == 13);
}
