#include "nodes/vlm/query_vlm.hpp"

#include <atomic>
#include <optional>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "base/errors.hpp"
#include "base/http_post.hpp"
#include "base/random.hpp"
#include "nodes/vlm/chat_request.hpp"

namespace gslift {

uint64_t request_seed(uint64_t seed, size_t view, int round) {
  // stream_seed with (view, round) in the places of (purpose, index), cut to 31 bits: nearby
  // pairs get unrelated seeds.
  return stream_seed(seed, view, static_cast<uint64_t>(round)) >> 33;
}

std::vector<std::vector<VlmRoundReply>> query_vlm(const std::vector<VlmImage>& images,
                                                  const std::string& prompt,
                                                  const VlmQueryOptions& options,
                                                  const std::function<bool()>& cancelled) {
  const int rounds = std::max(options.rounds, 0);
  std::vector<std::vector<VlmRoundReply>> replies(images.size(),
                                                  std::vector<VlmRoundReply>(rounds));
  JsonEndpoint endpoint;
  endpoint.url = options.url;
  endpoint.api_key = options.api_key;
  endpoint.timeout_s = options.timeout_s;
  endpoint.retries = options.retries;
  endpoint.backoff_s = options.backoff_s;
  const size_t requests = images.size() * rounds;
  // Of the requests that failed, the first in (view, round) order is reported, whichever finished
  // first.
  std::vector<std::optional<std::string>> errors(requests);
  std::atomic<bool> stop{false};
  tbb::task_arena arena(std::max(options.concurrency, 1));
  arena.execute([&] {
    tbb::parallel_for(size_t(0), requests, [&](size_t r) {
      if (stop || (cancelled && cancelled())) {
        stop = true;
        return;
      }
      const size_t v = r / rounds;
      const int k = static_cast<int>(r % rounds);
      const std::string where =
          options.url + " (view '" + images[v].name + "', round " + std::to_string(k) + ")";
      ChatRequest request;
      request.model = options.model;
      request.prompt = prompt;
      request.image_png = images[v].png;
      request.temperature = options.temperature;
      request.max_tokens = options.max_tokens;
      request.seed = request_seed(options.seed, v, k);
      const std::string body = build_chat_request(request);
      try {
        int attempts = 0;
        const std::string reply = post_json(endpoint, body, where, &attempts);
        replies[v][k].content = chat_reply_content(reply, where);
        replies[v][k].attempts = attempts;
      } catch (const InputError& e) {
        errors[r] = e.what();
        stop = true;  // the server is unusable: do not send the remaining requests
      }
    });
  });
  for (const auto& e : errors)
    if (e) throw InputError("vlm.query: " + *e);
  return replies;
}

const ParamTable<VlmQueryOptions>& vlm_query_param_table() {
  using O = VlmQueryOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("url", &O::url,
               "chat-completions endpoint, e.g. http://127.0.0.1:8000/v1/chat/completions")
          .required()
          .add("model", &O::model, "served model name sent in the request")
          .add("rounds", &O::rounds, "requests per view (LangOR: 5)", 1, 100)
          .add("temperature", &O::temperature, "sampling temperature; > 0 so rounds differ", 0, 2)
          .add("max_tokens", &O::max_tokens, "reply length limit", 16)
          .add("timeout_s", &O::timeout_s, "per-request time limit, connect included", 0.01)
          .add("retries", &O::retries,
               "extra attempts after a timeout, refused connection, 429 or 5xx", 0, 20)
          .add("backoff_s", &O::backoff_s, "sleep before retry k: backoff_s x 2^(k-1)", 0)
          .add("concurrency", &O::concurrency, "requests in flight at once", 1, 64);
  return table;
}

}  // namespace gslift
