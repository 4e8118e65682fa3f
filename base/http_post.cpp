#include "base/http_post.hpp"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <thread>

#include <curl/curl.h>

#include "base/errors.hpp"

namespace gslift {
namespace {

struct BodySink {
  std::string* body;
  size_t max_bytes;
  bool too_large = false;
};

size_t append_body(char* data, size_t size, size_t count, void* out) {
  auto* sink = static_cast<BodySink*>(out);
  if (sink->body->size() + size * count > sink->max_bytes) {
    sink->too_large = true;
    return 0;  // less than given: libcurl stops the transfer (CURLE_WRITE_ERROR)
  }
  sink->body->append(data, size * count);
  return size * count;
}

}  // namespace

HttpResult http_post_json(const std::string& url, const std::string& body,
                          const std::vector<std::string>& headers, double timeout_s,
                          size_t max_body_bytes) {
  // curl_global_init is not thread-safe and must run once before any handle exists.
  static std::once_flag init;
  std::call_once(init, [] { curl_global_init(CURL_GLOBAL_DEFAULT); });

  HttpResult result;
  CURL* curl = curl_easy_init();
  if (!curl) {
    result.transport_failed = true;
    result.error = "libcurl could not create a handle";
    return result;
  }
  curl_slist* list = curl_slist_append(nullptr, "Content-Type: application/json");
  // No "Expect: 100-continue" round trip for large image bodies.
  list = curl_slist_append(list, "Expect:");
  for (const auto& h : headers) list = curl_slist_append(list, h.c_str());
  char message[CURL_ERROR_SIZE] = {};
  curl_easy_setopt(curl, CURLOPT_URL, url.c_str());
  curl_easy_setopt(curl, CURLOPT_HTTPHEADER, list);
  curl_easy_setopt(curl, CURLOPT_POSTFIELDS, body.data());
  curl_easy_setopt(curl, CURLOPT_POSTFIELDSIZE_LARGE, static_cast<curl_off_t>(body.size()));
  curl_easy_setopt(curl, CURLOPT_WRITEFUNCTION, append_body);
  BodySink sink{&result.body, max_body_bytes};
  curl_easy_setopt(curl, CURLOPT_WRITEDATA, &sink);
  // A declared Content-Length past the cap fails before any byte is read.
  curl_easy_setopt(curl, CURLOPT_MAXFILESIZE_LARGE, static_cast<curl_off_t>(max_body_bytes));
  curl_easy_setopt(curl, CURLOPT_TIMEOUT_MS, static_cast<long>(std::ceil(timeout_s * 1000)));
  curl_easy_setopt(curl, CURLOPT_NOSIGNAL, 1L);  // timeouts without SIGALRM: safe in threads
  curl_easy_setopt(curl, CURLOPT_ERRORBUFFER, message);
  const CURLcode code = curl_easy_perform(curl);
  if (sink.too_large || code == CURLE_FILESIZE_EXCEEDED) {
    result.too_large = true;
    result.body.clear();
    result.error = "the reply is larger than " + std::to_string(max_body_bytes >> 20) + " MiB";
  } else if (code != CURLE_OK) {
    result.transport_failed = true;
    result.timed_out = code == CURLE_OPERATION_TIMEDOUT;
    result.error = message[0] ? message : curl_easy_strerror(code);
  } else {
    curl_easy_getinfo(curl, CURLINFO_RESPONSE_CODE, &result.status);
  }
  curl_slist_free_all(list);
  curl_easy_cleanup(curl);
  return result;
}

bool retryable(const HttpResult& result) {
  if (result.too_large) return false;
  return result.transport_failed || result.status == 429 || result.status >= 500;
}

HttpResult post_with_retries(const std::function<HttpResult()>& attempt, int retries,
                             double backoff_s, int* attempts_made) {
  HttpResult result;
  int made = 0;
  for (int k = 0; k <= retries; ++k) {
    if (k > 0)
      std::this_thread::sleep_for(
          std::chrono::duration<double>(backoff_s * std::ldexp(1.0, k - 1)));
    result = attempt();
    ++made;
    if (!retryable(result)) break;
  }
  if (attempts_made) *attempts_made = made;
  return result;
}

std::string redact(std::string text, const std::string& secret) {
  if (secret.empty()) return text;
  for (size_t at = text.find(secret); at != std::string::npos; at = text.find(secret, at))
    text.replace(at, secret.size(), "[api key]");
  return text;
}

std::string post_json(const JsonEndpoint& endpoint, const std::string& body,
                      const std::string& where, int* attempts) {
  std::vector<std::string> headers;
  if (!endpoint.api_key.empty()) headers.push_back("Authorization: Bearer " + endpoint.api_key);
  int made = 0;
  HttpResult result = post_with_retries(
      [&] {
        return http_post_json(endpoint.url, body, headers, endpoint.timeout_s,
                              endpoint.max_body_bytes);
      },
      endpoint.retries, endpoint.backoff_s, &made);
  if (attempts) *attempts = made;
  // Before anything is cut or parsed, so that no part of the key survives.
  result.body = redact(std::move(result.body), endpoint.api_key);
  result.error = redact(std::move(result.error), endpoint.api_key);
  const std::string tries = " after " + std::to_string(made) + " attempt(s)";
  if (result.too_large) throw InputError(where + ": " + result.error + " (not retried)");
  if (result.transport_failed)
    throw InputError(where + ": " + (result.timed_out ? "timed out" : "request failed") + tries +
                     ": " + result.error);
  if (result.status >= 400)
    throw InputError(where + ": HTTP " + std::to_string(result.status) + tries + ": " +
                     result.body.substr(0, 200));
  return std::move(result.body);
}

std::string api_key_from_env(const std::string& node, const std::string& name) {
  if (name.empty()) return {};
  const char* key = std::getenv(name.c_str());
  if (!key || !*key)
    throw InputError(node + ": environment variable " + name + " (param api_key_env) is not set");
  return key;
}

}  // namespace gslift
