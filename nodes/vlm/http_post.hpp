// One HTTP POST of a JSON body (libcurl), and the retry policy vlm.query puts around it.
#pragma once

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

}  // namespace gslift
