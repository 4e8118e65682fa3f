#include "nodes/text/register.hpp"

#include <memory>

#include "base/cache_root.hpp"
#include "nodes/scene/context_prompt.hpp"
#include "nodes/text/embeddings_text_encoder.hpp"
#include "nodes/text/hashing_text_encoder.hpp"
#include "nodes/text/lexical_text_encoder.hpp"
#include "nodes/text/table_text_encoder.hpp"

namespace gslift {
namespace {

enum class TextEncoderKind { Hashing, Table, Lexical, Embeddings };

// text.encoder's params: which encoder, and what it needs.
struct TextEncoderParams {
  TextEncoderKind kind = TextEncoderKind::Hashing;
  int dim = 384;      // hashing, and lexical's hashing part
  std::string table;  // table: the embeddings file
  // lexical: the classes to match onto. Relative like boxes.prompt's (relative to the graph file
  // that sets it, else to the current directory).
  std::string vocabulary = "graphs/vocabulary/or.yaml";
  // embeddings: the server, as vlm.query's (url, model, api_key_env, timeout_s, retries,
  // backoff_s), and the cosine from which a text means a class.
  std::string url, model, api_key_env;
  double timeout_s = 120;
  int retries = 2;
  double backoff_s = 1;
  double match_threshold = 0.5;
};

const ParamTable<TextEncoderParams>& text_encoder_param_table() {
  using P = TextEncoderParams;
  static const EnumNames<TextEncoderKind> kinds = {{TextEncoderKind::Hashing, "hashing"},
                                                   {TextEncoderKind::Table, "table"},
                                                   {TextEncoderKind::Lexical, "lexical"},
                                                   {TextEncoderKind::Embeddings, "embeddings"}};
  static const ParamTable<P> table =
      ParamTable<P>()
          .add("kind", &P::kind, kinds,
               "hashing: built-in subword hashing; table: precomputed embeddings from `table`; "
               "lexical: WordNet synonyms, hypernyms and glosses onto the classes of `vocabulary` "
               "(docs/text_queries.md); embeddings: an OpenAI-compatible /v1/embeddings server")
          .add("dim", &P::dim, "hashing: embedding width (lexical: of its hashing part)", 1, 65536)
          .add("table", &P::table,
               "table: file of 'label<TAB>v1 .. vD' lines or a JSON {label: [..]} object")
          .path()
          .add("vocabulary", &P::vocabulary,
               "lexical: vocabulary file (graphs/vocabulary/or.yaml: names, aliases, "
               "descriptions); embeddings: its class names are embedded and cached")
          .path()
          .add("url", &P::url, "embeddings: server base url, e.g. http://127.0.0.1:8000")
          .add("model", &P::model, "embeddings: served model name sent in the request")
          .add("api_key_env", &P::api_key_env,
               "embeddings: environment variable holding a bearer token (never put a key in "
               "the YAML)")
          .add("timeout_s", &P::timeout_s, "embeddings: per-request time limit, connect included",
               0.01)
          .add("retries", &P::retries,
               "embeddings: extra attempts after a timeout, refused connection, 429 or 5xx", 0, 20)
          .add("backoff_s", &P::backoff_s, "embeddings: sleep before retry k: backoff_s x 2^(k-1)",
               0)
          .add("match_threshold", &P::match_threshold,
               "embeddings: cosine from which a text counts as meaning a class (model-dependent)",
               -1, 1);
  return table;
}

void run_text_encoder(NodeContext& ctx, const TextEncoderParams& p) {
  std::shared_ptr<const TextEncoder> encoder;
  if (p.kind == TextEncoderKind::Table) {
    if (p.table.empty())
      throw InputError("text.encoder: kind 'table' needs the param 'table' (a file)");
    encoder = std::make_shared<const TableTextEncoder>(TableTextEncoder::load(p.table));
  } else if (p.kind == TextEncoderKind::Lexical) {
    encoder = std::make_shared<const LexicalTextEncoder>(load_vocabulary(p.vocabulary), p.dim);
  } else if (p.kind == TextEncoderKind::Embeddings) {
    if (p.url.empty()) throw InputError("text.encoder: kind 'embeddings' needs the param 'url'");
    EmbeddingsOptions o;
    o.url = p.url;
    o.model = p.model;
    o.endpoint.api_key = api_key_from_env("text.encoder", p.api_key_env);
    o.endpoint.timeout_s = p.timeout_s;
    o.endpoint.retries = p.retries;
    o.endpoint.backoff_s = p.backoff_s;
    o.match_threshold = static_cast<float>(p.match_threshold);
    const auto names = load_vocabulary(p.vocabulary).class_names();
    encoder = std::make_shared<const EmbeddingsTextEncoder>(
        o, names, embeddings_cache_file(user_cache_root(), p.url, p.model));
  } else {
    encoder = std::make_shared<const HashingTextEncoder>(p.dim);
  }
  ctx.record("encoder", encoder->name());
  ctx.record("dim", static_cast<double>(encoder->dim()));
  ctx.output<TextEncoder>("encoder", encoder);
}

}  // namespace

void register_text_nodes(Registry& registry) {
  NodeSpec spec{
      "text.encoder",
      "the text encoder that labels and queries share (built-in hashing, a table file, WordNet "
      "onto a vocabulary, or an embeddings server)",
      {},
      {{"encoder", "TextEncoder", "encodes text to an L2-normalised vector"}}};
  registry.add(std::move(spec), text_encoder_param_table(), run_text_encoder);
}

}  // namespace gslift
