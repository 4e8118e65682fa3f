// text.encoder as a graph node, run through the inline-graph harness.
#include "nodes/scene/text_encoder.hpp"
#include "nodes/text/register.hpp"
#include "runtime/executor.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("text.encoder node builds the requested encoder") {
  Registry reg;
  register_text_nodes(reg);
  const RunResult hashing =
      run_graph_text("graph: t\nnodes:\n  e: {type: text.encoder, params: {dim: 64}}\n", reg);
  REQUIRE(hashing.ok());
  const auto enc = hashing.values.at("e.encoder").get<TextEncoder>();
  CHECK(enc->dim() == 64);
  CHECK(enc->name() == "hashing-64");

  const std::string table = test::test_data("text/table.tsv").string();
  const RunResult from_table =
      run_graph_text("graph: t\nnodes:\n  e: {type: text.encoder, params: {kind: table, table: \"" +
                         table + "\"}}\n",
                     reg);
  REQUIRE(from_table.ok());
  CHECK(from_table.values.at("e.encoder").get<TextEncoder>()->dim() == 4);

  const RunResult missing =
      run_graph_text("graph: t\nnodes:\n  e: {type: text.encoder, params: {kind: table}}\n", reg);
  REQUIRE_FALSE(missing.ok());
  CHECK(missing.error->kind == RunError::Kind::BadInput);
}
