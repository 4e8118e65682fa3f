// The OpenAI-compatible chat-completions exchange of vlm.query: the request body that shows a VLM
// one image and the grounding prompt, and the reply text taken out of the response body. Plain
// strings in and out, so both are tested without a server.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace gslift {

// Standard base64 (RFC 4648, with padding), for the image's data URL.
std::string base64_encode(std::string_view bytes);

struct ChatRequest {
  std::string model;         // the served model name (vLLM: --served-model-name)
  std::string prompt;        // the grounding prompt (boxes.prompt)
  std::string image_png;     // the encoded PNG the model is shown
  double temperature = 0.7;  // > 0 so that rounds differ (the multi-round perceptor's point)
  int max_tokens = 2048;
  std::optional<uint64_t> seed;  // per-request sampling seed (vLLM honours it): reproducible rounds
};

// {"model", "messages": [{"role": "user", "content": [{"type": "image_url", "image_url": {"url":
// "data:image/png;base64,..."}}, {"type": "text", "text": prompt}]}], "temperature", "max_tokens",
// "seed"?}: the image first, as the Qwen-VL chat templates expect.
std::string build_chat_request(const ChatRequest& request);

// choices[0].message.content of a chat-completions response body. Throws InputError starting with
// `source` when the body is not JSON, carries an "error" object, or has no string content.
std::string chat_reply_content(const std::string& body, const std::string& source);

}  // namespace gslift
