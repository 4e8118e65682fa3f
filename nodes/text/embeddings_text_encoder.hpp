// Text embeddings from a server (issue 30): POST {"model": m, "input": [texts]} to an
// OpenAI-compatible /v1/embeddings endpoint (vLLM, llama.cpp's server and Ollama serve it) and
// read data[i].embedding. Calls go through vlm.query's client (base/http_post.hpp: the same
// timeouts, retries with backoff, bearer key and redaction, failures as InputError naming the url).
//
// The vocabulary's embeddings are asked for once, in one request, and kept per (server, model) in
// <gslift cache>/embeddings/ (base/cache_root.hpp), so a later run with the same model sends only
// its queries. Every other text is asked for when first encoded and kept in memory for the run.
#pragma once

#include <filesystem>
#include <map>
#include <mutex>
#include <vector>

#include "base/http_post.hpp"
#include "nodes/scene/text_encoder.hpp"

namespace gslift {

struct EmbeddingsOptions {
  std::string url;        // server base (http://127.0.0.1:8000) or the full .../v1/embeddings
  std::string model;      // served model name
  JsonEndpoint endpoint;  // timeout_s, retries, backoff_s, api_key (url is filled from `url`)
  float match_threshold = 0.5f;  // cosine from which a text means a class (model-dependent)
};

// The endpoint of a base url: "<base>/v1/embeddings" unless it already ends that way.
std::string embeddings_url(const std::string& url);

// The cache file of (url, model) under cache_root: embeddings/<model>-<16 hex digits>.json.
std::filesystem::path embeddings_cache_file(const std::filesystem::path& cache_root,
                                            const std::string& url, const std::string& model);

class EmbeddingsTextEncoder : public TextEncoder {
 public:
  // Reads `cache_file` (when it exists and is for this model), asks the server for the texts of
  // `vocabulary` it lacks in one request, and writes the file back when anything was added (an
  // empty cache_file: no file). Throws InputError when the server fails or answers with a body
  // that is not an embeddings response of one vector per input, all of one width.
  EmbeddingsTextEncoder(EmbeddingsOptions options, const std::vector<std::string>& vocabulary,
                        std::filesystem::path cache_file);

  Eigen::VectorXf encode(const std::string& text) const override;
  int dim() const override { return dim_; }
  std::string name() const override { return "embeddings:" + options_.model; }
  float match_threshold() const override { return options_.match_threshold; }

  int requests() const;  // made so far (vocabulary and queries)

 private:
  std::vector<Eigen::VectorXf> fetch(const std::vector<std::string>& texts) const;

  EmbeddingsOptions options_;
  std::filesystem::path cache_file_;
  int dim_ = 0;
  mutable std::mutex mutex_;
  mutable std::map<std::string, Eigen::VectorXf> known_;
  mutable int requests_ = 0;
};

}  // namespace gslift
