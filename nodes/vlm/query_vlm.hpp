// The multi-round VLM perceptor against a live server (LangOR §1.1): every selected view's image
// and the grounding prompt go to an OpenAI-compatible chat-completions endpoint `rounds` times;
// the raw replies come back in (view, round) order whatever the concurrency.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "param/param_table.hpp"

namespace gslift {

struct VlmQueryOptions {
  std::string url;           // e.g. http://127.0.0.1:8000/v1/chat/completions
  std::string model;         // served model name
  std::string api_key;       // bearer token, empty = no Authorization header
  int rounds = 5;            // LangOR: 5 rounds per image
  double temperature = 0.7;  // [decision] sampling on, so rounds differ; 0 would repeat one answer
  int max_tokens = 2048;
  double timeout_s = 120;  // per request, connect included (a 7B VLM answers in seconds)
  int retries = 2;         // extra attempts after a timeout, a refused connection, 429 or 5xx
  double backoff_s = 1;    // sleep before retry k: backoff_s x 2^(k-1)
  int concurrency = 2;     // requests in flight at once
  uint64_t seed = 0;       // run seed: request seeds are derived from (seed, view, round)
};

// The params of the request (vlm.query): every field above but api_key (read from the
// environment, never from a graph) and seed (the node's seed).
const ParamTable<VlmQueryOptions>& vlm_query_param_table();

// One view the VLM is shown: its name (for messages) and the PNG bytes sent.
struct VlmImage {
  std::string name;
  std::string png;
};

struct VlmRoundReply {
  std::string content;  // choices[0].message.content, raw
  int attempts = 0;     // HTTP attempts made (1 = no retry)
};

// Sampling seed of one request (31 bits, accepted by every server), from (seed, view, round).
uint64_t request_seed(uint64_t seed, size_t view, int round);

// replies[v][k] for images[v], round k. Throws InputError naming the url, the view and the round
// when a request still fails after its retries (transport error, HTTP status >= 400) or the body is
// not a chat-completions response. cancelled() is polled before each request; when it returns true
// the remaining requests are skipped and the function returns what it has (the caller throws).
std::vector<std::vector<VlmRoundReply>> query_vlm(const std::vector<VlmImage>& images,
                                                  const std::string& prompt,
                                                  const VlmQueryOptions& options,
                                                  const std::function<bool()>& cancelled = {});

}  // namespace gslift
