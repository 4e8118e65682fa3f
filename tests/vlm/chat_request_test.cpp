// The chat-completions exchange without a server: base64, the request body, reply extraction.
#include <set>

#include <nlohmann/json.hpp>

#include "base/http_post.hpp"
#include "nodes/vlm/chat_request.hpp"
#include "nodes/vlm/query_vlm.hpp"
#include "runtime/node.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("base64 matches RFC 4648's test vectors") {
  CHECK(base64_encode("") == "");
  CHECK(base64_encode("f") == "Zg==");
  CHECK(base64_encode("fo") == "Zm8=");
  CHECK(base64_encode("foo") == "Zm9v");
  CHECK(base64_encode("foob") == "Zm9vYg==");
  CHECK(base64_encode("fooba") == "Zm9vYmE=");
  CHECK(base64_encode("foobar") == "Zm9vYmFy");
  CHECK(base64_encode(std::string("\xff\x00\xfe", 3)) == "/wD+");
}

TEST_CASE("the request shows the image first, then the prompt, with the sampling settings") {
  ChatRequest r;
  r.model = "qwen2.5-vl-7b";
  r.prompt = "Find the surgeon.";
  r.image_png = "foo";
  r.temperature = 0.5;
  r.max_tokens = 100;
  r.seed = 42;
  const auto j = nlohmann::json::parse(build_chat_request(r));
  CHECK(j["model"] == "qwen2.5-vl-7b");
  CHECK(j["temperature"] == 0.5);
  CHECK(j["max_tokens"] == 100);
  CHECK(j["seed"] == 42);
  const auto& content = j["messages"][0]["content"];
  CHECK(j["messages"][0]["role"] == "user");
  CHECK(content[0]["type"] == "image_url");
  CHECK(content[0]["image_url"]["url"] == "data:image/png;base64,Zm9v");
  CHECK(content[1]["type"] == "text");
  CHECK(content[1]["text"] == "Find the surgeon.");
  r.seed.reset();
  CHECK_FALSE(nlohmann::json::parse(build_chat_request(r)).contains("seed"));
}

TEST_CASE("the reply text comes out of choices[0].message.content, anything else is named") {
  CHECK(chat_reply_content(R"({"choices": [{"message": {"role": "assistant", "content": "hi"}}]})",
                           "s") == "hi");
  CHECK_THROWS_WITH(chat_reply_content("{\"choices\": [", "srv"),
                    Catch::StartsWith("srv: the response is not JSON"));
  CHECK_THROWS_WITH(chat_reply_content(R"({"error": {"message": "model not found"}})", "srv"),
                    Catch::Contains("model not found"));
  CHECK_THROWS_WITH(chat_reply_content(R"({"choices": []})", "srv"),
                    Catch::Contains("no choices[0].message.content"));
  CHECK_THROWS_WITH(chat_reply_content(R"({"choices": [{"message": {"content": 3}}]})", "srv"),
                    Catch::Contains("no choices[0].message.content"));
}

TEST_CASE("retries: transport errors, 429 and 5xx are retried with backoff, 4xx is not") {
  auto run = [](std::vector<HttpResult> script, int retries, int* attempts) {
    size_t n = 0;
    return post_with_retries([&] { return script[std::min(n++, script.size() - 1)]; }, retries, 0.0,
                             attempts);
  };
  HttpResult refused, timeout, s500, s429, s400, ok;
  refused.transport_failed = true;
  timeout.transport_failed = timeout.timed_out = true;
  s500.status = 500;
  s429.status = 429;
  s400.status = 400;
  ok.status = 200;
  int attempts = 0;
  CHECK(run({refused, timeout, s500, ok}, 3, &attempts).status == 200);
  CHECK(attempts == 4);
  CHECK(run({s429, ok}, 3, &attempts).status == 200);
  CHECK(attempts == 2);
  CHECK(run({s400, ok}, 3, &attempts).status == 400);
  CHECK(attempts == 1);
  CHECK(run({s500}, 2, &attempts).status == 500);
  CHECK(attempts == 3);
}

TEST_CASE("request seeds differ per view and round, stay in 31 bits and repeat for a seed") {
  std::set<uint64_t> seen;
  for (size_t v = 0; v < 5; ++v)
    for (int k = 0; k < 5; ++k) {
      const uint64_t s = request_seed(7, v, k);
      CHECK(s < (uint64_t(1) << 31));
      CHECK(s == request_seed(7, v, k));
      seen.insert(s);
    }
  CHECK(seen.size() == 25);
  CHECK(request_seed(7, 0, 0) != request_seed(8, 0, 0));
}
