#include "nodes/vlm/chat_request.hpp"

#include <nlohmann/json.hpp>

#include "base/errors.hpp"
#include "base/json_read.hpp"
#include "base/utf8.hpp"

namespace gslift {

std::string base64_encode(std::string_view bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  auto byte = [&](size_t k) { return static_cast<uint32_t>(static_cast<unsigned char>(bytes[k])); };
  for (; i + 3 <= bytes.size(); i += 3) {
    const uint32_t v = byte(i) << 16 | byte(i + 1) << 8 | byte(i + 2);
    for (int s = 18; s >= 0; s -= 6) out.push_back(kAlphabet[(v >> s) & 63]);
  }
  const size_t rest = bytes.size() - i;
  if (rest > 0) {
    const uint32_t v = byte(i) << 16 | (rest == 2 ? byte(i + 1) << 8 : 0u);
    out.push_back(kAlphabet[(v >> 18) & 63]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(rest == 2 ? kAlphabet[(v >> 6) & 63] : '=');
    out.push_back('=');
  }
  return out;
}

std::string build_chat_request(const ChatRequest& request) {
  using nlohmann::json;
  json content = json::array();
  content.push_back(
      {{"type", "image_url"},
       {"image_url", {{"url", "data:image/png;base64," + base64_encode(request.image_png)}}}});
  content.push_back({{"type", "text"}, {"text", request.prompt}});
  json body = {{"model", request.model},
               {"messages", json::array({{{"role", "user"}, {"content", content}}})},
               {"temperature", request.temperature},
               {"max_tokens", request.max_tokens}};
  if (request.seed) body["seed"] = *request.seed;
  return body.dump();
}

std::string chat_reply_content(const std::string& body, const std::string& source) {
  const nlohmann::json j = parse_json_or_discarded(body);
  if (j.is_discarded())
    throw InputError(source + ": the response is not JSON: " + printable(body, 80));
  if (j.is_object() && j.contains("error"))
    throw InputError(source +
                     ": the server answered with an error: " + printable(j["error"].dump()));
  const nlohmann::json* content = nullptr;
  if (j.is_object() && j.contains("choices") && j["choices"].is_array() && !j["choices"].empty()) {
    const auto& choice = j["choices"][0];
    if (choice.is_object() && choice.contains("message") && choice["message"].is_object() &&
        choice["message"].contains("content"))
      content = &choice["message"]["content"];
  }
  if (!content || !content->is_string())
    throw InputError(source + ": the response has no choices[0].message.content string");
  return content->get<std::string>();
}

}  // namespace gslift
