#include "nodes/text/embeddings_text_encoder.hpp"

#include <cctype>
#include <cstdio>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/errors.hpp"
#include "base/hash.hpp"
#include "base/json_read.hpp"

namespace gslift {
namespace {

constexpr const char* kSuffix = "/v1/embeddings";

// A reply carries one float vector per input; 64 MiB holds thousands of 4096-d vectors as text.
constexpr size_t kMaxEmbeddingsBytes = size_t(64) << 20;

Eigen::VectorXf normalised(const std::vector<float>& values, const std::string& where) {
  Eigen::VectorXf v =
      Eigen::Map<const Eigen::VectorXf>(values.data(), static_cast<Eigen::Index>(values.size()));
  if (v.size() == 0 || !v.allFinite() || v.norm() == 0)
    throw InputError(where + ": an embedding is empty, zero or not finite");
  return v / v.norm();
}

}  // namespace

std::string embeddings_url(const std::string& url) {
  std::string base = url;
  while (!base.empty() && base.back() == '/') base.pop_back();
  const std::string suffix = kSuffix;
  if (base.size() >= suffix.size() &&
      base.compare(base.size() - suffix.size(), suffix.size(), suffix) == 0)
    return base;
  return base + suffix;
}

std::filesystem::path embeddings_cache_file(const std::filesystem::path& cache_root,
                                            const std::string& url, const std::string& model) {
  std::string safe;
  for (const char c : model)
    safe.push_back(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' ? c : '_');
  char digest[17];
  std::snprintf(digest, sizeof digest, "%016llx",
                static_cast<unsigned long long>(fnv1a64(embeddings_url(url) + "\n" + model)));
  return cache_root / "embeddings" / (safe + "-" + digest + ".json");
}

EmbeddingsTextEncoder::EmbeddingsTextEncoder(EmbeddingsOptions options,
                                             const std::vector<std::string>& vocabulary,
                                             std::filesystem::path cache_file)
    : options_(std::move(options)), cache_file_(std::move(cache_file)) {
  if (options_.url.empty()) throw InputError("text.encoder embeddings: no url");
  if (vocabulary.empty()) throw InputError("text.encoder embeddings: no vocabulary to embed");
  options_.endpoint.url = embeddings_url(options_.url);
  options_.endpoint.max_body_bytes = kMaxEmbeddingsBytes;
  if (!cache_file_.empty() && std::filesystem::exists(cache_file_)) {
    // A cache that cannot be read is asked for again rather than trusted.
    try {
      std::ifstream in(cache_file_);
      const nlohmann::json doc = parse_json(
          std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()));
      if (doc.at("model") == options_.model && doc.at("url") == options_.endpoint.url)
        for (const auto& [text, values] : doc.at("embeddings").items()) {
          Eigen::VectorXf v = normalised(values.get<std::vector<float>>(), cache_file_.string());
          if (dim_ == 0) dim_ = static_cast<int>(v.size());
          if (v.size() == dim_) known_.emplace(text, std::move(v));
        }
    } catch (const std::exception&) {
      known_.clear();
      dim_ = 0;
    }
  }
  std::vector<std::string> missing;
  for (const std::string& text : vocabulary)
    if (!known_.count(text)) missing.push_back(text);
  if (missing.empty()) return;
  const std::vector<Eigen::VectorXf> fetched = fetch(missing);
  if (dim_ == 0) dim_ = static_cast<int>(fetched.front().size());
  for (size_t i = 0; i < missing.size(); ++i) known_[missing[i]] = fetched[i];
  if (cache_file_.empty()) return;
  nlohmann::json doc = {{"model", options_.model}, {"url", options_.endpoint.url}};
  nlohmann::json& table = doc["embeddings"] = nlohmann::json::object();
  for (const auto& [text, v] : known_)
    table[text] = std::vector<float>(v.data(), v.data() + v.size());
  write_file_atomically(cache_file_, doc.dump());
}

std::vector<Eigen::VectorXf> EmbeddingsTextEncoder::fetch(
    const std::vector<std::string>& texts) const {
  const std::string where = "text.encoder embeddings: " + options_.endpoint.url;
  const nlohmann::json request = {{"model", options_.model}, {"input", texts}};
  const std::string body = post_json(options_.endpoint, request.dump(), where);
  ++requests_;
  std::vector<Eigen::VectorXf> out(texts.size());
  try {
    const nlohmann::json reply = parse_json(body);
    const nlohmann::json& data = reply.at("data");
    if (!data.is_array() || data.size() != texts.size())
      throw InputError(where + ": expected " + std::to_string(texts.size()) +
                       " embeddings in 'data', got " +
                       (data.is_array() ? std::to_string(data.size()) : data.type_name()));
    for (size_t i = 0; i < data.size(); ++i) {
      // Servers may answer out of order; "index" says which input an entry is for.
      const size_t at = data[i].contains("index") ? data[i].at("index").get<size_t>() : i;
      if (at >= texts.size() || out[at].size() != 0)
        throw InputError(where + ": entry " + std::to_string(i) + " has a bad or repeated index");
      out[at] = normalised(data[i].at("embedding").get<std::vector<float>>(), where);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where + ": not an embeddings response (" + e.what() +
                     "): " + body.substr(0, 200));
  }
  for (const Eigen::VectorXf& v : out) {
    const int d = static_cast<int>(v.size());
    const int expected = dim_ ? dim_ : static_cast<int>(out.front().size());
    if (d != expected)
      throw InputError(where + ": embeddings of " + std::to_string(d) + " and " +
                       std::to_string(expected) + " values (a different model than the cache?)");
  }
  return out;
}

Eigen::VectorXf EmbeddingsTextEncoder::encode(const std::string& text) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (const auto it = known_.find(text); it != known_.end()) return it->second;
  Eigen::VectorXf v = fetch({text}).front();
  known_.emplace(text, v);
  return v;
}

int EmbeddingsTextEncoder::requests() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return requests_;
}

}  // namespace gslift
