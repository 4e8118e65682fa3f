// One HTTP POST of a JSON body (libcurl), and the policy vlm.query and the embeddings text encoder
// put around it (retries, the API key, failures as InputError).
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace gslift {

struct HttpResult {
  // Transport failure (connection refused, timeout, DNS): no HTTP status. error says which.
  bool transport_failed = false;
  bool timed_out = false;
  bool too_large = false;  // the body passed max_body_bytes and the transfer was stopped
  long status = 0;
  std::string body;
  std::string error;
};

// A chat-completions reply is text of at most max_tokens tokens (kilobytes); a body past this is a
// misbehaving server or proxy, stopped before it fills memory.
constexpr size_t kMaxReplyBytes = size_t(8) << 20;

// POSTs body with Content-Type: application/json plus `headers` ("Name: value"). timeout_s bounds
// the whole exchange (connect included); a reply body longer than max_body_bytes stops the
// transfer (too_large). Never throws for network errors: they are reported in the result, so the
// caller decides what to retry.
HttpResult http_post_json(const std::string& url, const std::string& body,
                          const std::vector<std::string>& headers, double timeout_s,
                          size_t max_body_bytes = kMaxReplyBytes);

// Whether a result is worth another attempt: transport failures and timeouts (the server may be
// starting or busy), 429 (rate limited) and 5xx. Other 4xx mean the request itself is wrong, and
// an oversized reply would only come again.
bool retryable(const HttpResult& result);

// Calls attempt() up to 1 + retries times while its result is retryable, sleeping backoff_s,
// 2 backoff_s, 4 backoff_s, ... between attempts. Returns the last result and the attempts made.
HttpResult post_with_retries(const std::function<HttpResult()>& attempt, int retries,
                             double backoff_s, int* attempts_made = nullptr);

// `text` with every occurrence of `secret` replaced by "[api key]" (nothing when secret is empty):
// the key never leaves in a message or a stored reply, even from a server that echoes the
// request's headers back (some proxies do on errors).
std::string redact(std::string text, const std::string& secret);

// One endpoint and how it is called.
struct JsonEndpoint {
  std::string url;
  std::string api_key;  // bearer token, empty = no Authorization header
  double timeout_s = 120;
  int retries = 2;
  double backoff_s = 1;
  size_t max_body_bytes = kMaxReplyBytes;
};

// POSTs body with post_with_retries and returns the body of a reply below HTTP 400 (key redacted).
// Throws InputError "<where>: timed out after N attempt(s): ...", "...: HTTP 503 after N
// attempt(s): <start of the body>" or, for an oversized reply (not retried), "...: <error>". The
// attempts made go to *attempts when given.
std::string post_json(const JsonEndpoint& endpoint, const std::string& body,
                      const std::string& where, int* attempts = nullptr);

// The value of the environment variable `name` (a node's api_key_env param), for `node`'s
// messages; empty name = no key. Throws InputError when the variable is unset or empty.
std::string api_key_from_env(const std::string& node, const std::string& name);

}  // namespace gslift
