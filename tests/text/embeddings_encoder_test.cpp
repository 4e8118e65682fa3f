// The embeddings text encoder (nodes/text/embeddings_text_encoder.hpp) against a local stand-in
// for an OpenAI-compatible /v1/embeddings server (tests/vlm/loopback_server.hpp). The stand-in
// answers with fixed vectors: these tests check the protocol (request, reply, order, cache,
// retries, failures), not a model; no real embedding model is reachable from the tests.
#include <catch2/catch.hpp>

#include <map>

#include <nlohmann/json.hpp>

#include "nodes/scene/vocabulary_match.hpp"
#include "nodes/text/embeddings_text_encoder.hpp"
#include "tests/test_support.hpp"
#include "tests/vlm/loopback_server.hpp"

using namespace gslift;
using gslift::test::CannedResponse;
using gslift::test::LoopbackServer;

namespace {

// The stand-in's "model": a fixed 3-d vector per known text (unknown texts get (0, 0, 1)).
std::vector<float> stand_in_vector(const std::string& text) {
  static const std::map<std::string, std::vector<float>> table{{"anesthesia machine", {1, 0, 0}},
                                                               {"circulating nurse", {0, 1, 0}},
                                                               {"patient", {0, 0.2f, 1}},
                                                               {"ventilator", {0.9f, 0.1f, 0}},
                                                               {"nurse", {0.1f, 0.9f, 0}}};
  const auto it = table.find(text);
  return it != table.end() ? it->second : std::vector<float>{0, 0, 1};
}

// One embedding per input, listed in reverse order with their "index" (servers may reorder).
std::string embeddings_reply(const std::string& request_body) {
  const auto request = nlohmann::json::parse(request_body);
  const auto& input = request.at("input");
  nlohmann::json data = nlohmann::json::array();
  for (size_t i = input.size(); i-- > 0;)
    data.push_back({{"object", "embedding"},
                    {"index", i},
                    {"embedding", stand_in_vector(input[i].get<std::string>())}});
  return nlohmann::json{{"object", "list"}, {"model", request.at("model")}, {"data", data}}.dump();
}

CannedResponse stand_in() {
  CannedResponse r;
  r.respond = embeddings_reply;
  return r;
}

const std::vector<std::string> kVocabulary{"anesthesia machine", "circulating nurse", "patient"};

EmbeddingsOptions options_for(const LoopbackServer& server) {
  EmbeddingsOptions o;
  o.url = server.base_url();
  o.model = "stand-in";
  o.endpoint.timeout_s = 5;
  o.endpoint.retries = 2;
  o.endpoint.backoff_s = 0;
  return o;
}

}  // namespace

TEST_CASE("embeddings encoder: the protocol of /v1/embeddings (stand-in server, no model)") {
  LoopbackServer server({stand_in()});
  EmbeddingsOptions o = options_for(server);
  o.endpoint.api_key = "sk-test";
  const EmbeddingsTextEncoder enc(o, kVocabulary, {});
  CHECK(enc.dim() == 3);
  CHECK(enc.name() == "embeddings:stand-in");
  REQUIRE(server.bodies().size() == 1);  // the vocabulary in one request
  const auto first = nlohmann::json::parse(server.bodies()[0]);
  CHECK(first.at("model") == "stand-in");
  CHECK(first.at("input") == nlohmann::json(kVocabulary));
  CHECK(server.headers()[0].rfind("POST /v1/embeddings HTTP/1.1", 0) == 0);
  CHECK(server.headers()[0].find("Authorization: Bearer sk-test") != std::string::npos);
  // Reordered replies land on their inputs.
  CHECK(enc.encode("circulating nurse").isApprox(Eigen::Vector3f(0, 1, 0)));

  const VocabularyMatcher matcher(enc, kVocabulary);  // no request: the vocabulary is known
  CHECK(server.bodies().size() == 1);
  const auto v = matcher.match("ventilator");
  REQUIRE(v);
  CHECK(v->name == "anesthesia machine");
  CHECK(matcher.match("nurse")->name == "circulating nurse");
  REQUIRE(server.bodies().size() == 3);  // one request per new text
  CHECK(nlohmann::json::parse(server.bodies()[1]).at("input") ==
        nlohmann::json::array({"ventilator"}));
  enc.encode("ventilator");  // kept for the run
  CHECK(server.bodies().size() == 3);
  CHECK(enc.requests() == 3);
}

TEST_CASE("embeddings encoder: the vocabulary's embeddings are cached per model") {
  const auto dir = test::scratch_dir("embeddings_cache");
  LoopbackServer server({stand_in()});
  const EmbeddingsOptions o = options_for(server);
  const auto file = embeddings_cache_file(dir, o.url, o.model);
  CHECK(file.parent_path() == dir / "embeddings");
  CHECK(file.filename().string().rfind("stand-in-", 0) == 0);
  CHECK(embeddings_cache_file(dir, o.url, "other") != file);
  { const EmbeddingsTextEncoder first(o, kVocabulary, file); }
  REQUIRE(std::filesystem::exists(file));
  CHECK(server.bodies().size() == 1);
  const EmbeddingsTextEncoder again(o, kVocabulary, file);
  CHECK(server.bodies().size() == 1);  // nothing asked
  CHECK(again.dim() == 3);
  CHECK(again.encode("patient").isApprox(Eigen::Vector3f(0, 0.2f, 1).normalized()));
  // One more class: only it is asked for.
  auto more = kVocabulary;
  more.push_back("nurse");
  const EmbeddingsTextEncoder grown(o, more, file);
  REQUIRE(server.bodies().size() == 2);
  CHECK(nlohmann::json::parse(server.bodies()[1]).at("input") == nlohmann::json::array({"nurse"}));
}

TEST_CASE("embeddings encoder: retries and failures as vlm.query's") {
  SECTION("a 503 is retried") {
    CannedResponse busy;
    busy.status = 503;
    busy.body = "busy";
    LoopbackServer server({busy, stand_in()});
    const EmbeddingsTextEncoder enc(options_for(server), kVocabulary, {});
    CHECK(server.bodies().size() == 2);
  }
  SECTION("a 400 is not, and names the url") {
    CannedResponse bad;
    bad.status = 400;
    bad.body = "unknown model";
    LoopbackServer server({bad});
    CHECK_THROWS_WITH(
        EmbeddingsTextEncoder(options_for(server), kVocabulary, {}),
        Catch::Contains("/v1/embeddings: HTTP 400 after 1 attempt(s): unknown model"));
  }
  SECTION("a body that is not an embeddings response") {
    CannedResponse chat;
    chat.body = R"({"choices": []})";
    LoopbackServer server({chat});
    CHECK_THROWS_WITH(EmbeddingsTextEncoder(options_for(server), kVocabulary, {}),
                      Catch::Contains("not an embeddings response"));
  }
  SECTION("fewer embeddings than inputs") {
    CannedResponse short_reply;
    short_reply.body = R"({"data": [{"index": 0, "embedding": [1, 0]}]})";
    LoopbackServer server({short_reply});
    CHECK_THROWS_WITH(EmbeddingsTextEncoder(options_for(server), kVocabulary, {}),
                      Catch::Contains("expected 3 embeddings in 'data', got 1"));
  }
  SECTION("a server that never answers times out, after the retries") {
    CannedResponse hang;
    hang.hang = true;
    LoopbackServer server({hang});
    EmbeddingsOptions o = options_for(server);
    o.endpoint.timeout_s = 0.2;
    o.endpoint.retries = 1;
    CHECK_THROWS_WITH(EmbeddingsTextEncoder(o, kVocabulary, {}),
                      Catch::Contains("timed out after 2 attempt(s)"));
  }
}

TEST_CASE("embeddings encoder: the endpoint of a base url") {
  CHECK(embeddings_url("http://h:8000") == "http://h:8000/v1/embeddings");
  CHECK(embeddings_url("http://h:8000/") == "http://h:8000/v1/embeddings");
  CHECK(embeddings_url("http://h:8000/v1/embeddings") == "http://h:8000/v1/embeddings");
}
