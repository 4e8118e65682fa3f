#include "nodes/text/wordnet.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <mutex>
#include <tuple>
#include <vector>

#include "base/errors.hpp"

// Last: its macros (NOUN, VERB, ...) must not reach other headers.
#include <wn.h>

namespace gslift {
namespace {

std::mutex& wordnet_mutex() {
  static std::mutex m;
  return m;
}

std::string clean(const char* word) {
  std::string out(word);
  for (char& c : out)
    c = c == '_' ? ' ' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// The library takes char* and may write into it.
std::vector<char> c_string(const std::string& s) {
  std::vector<char> buf(s.begin(), s.end());
  for (char& c : buf) c = c == ' ' ? '_' : c;
  buf.push_back('\0');
  return buf;
}

void add_hypernyms(SynsetPtr synset, int depth, std::vector<std::string>& out) {
  if (depth <= 0) return;
  for (int i = 0; i < synset->ptrcount; ++i) {
    if (synset->ptrtyp[i] != HYPERPTR) continue;
    SynsetPtr parent = read_synset(synset->ppos[i], synset->ptroff[i], nullptr);
    if (!parent) continue;
    for (int w = 0; w < parent->wcount; ++w) out.push_back(clean(parent->words[w]));
    add_hypernyms(parent, depth - 1, out);
    free_synset(parent);
  }
}

// getindex looks up every spelling variant of a word (spaces, hyphens, underscores) at once and
// hands out the first; the rest wait in its static table for getindex(nullptr, pos) and are
// overwritten, unfreed, by the next lookup. Taking and freeing them keeps WordNet from leaking
// (LeakSanitizer found it in the sanitizer suite).
void drain_index(int pos) {
  while (IndexPtr rest = getindex(nullptr, pos)) free_index(rest);
}

std::vector<WordSense> read_senses(const std::string& lemma, int pos, int max_senses, int depth) {
  std::vector<WordSense> out;
  std::vector<char> word = c_string(lemma);
  IndexPtr index = getindex(word.data(), pos);
  if (!index) return out;
  for (int s = 0; s < index->off_cnt && s < max_senses; ++s) {
    SynsetPtr synset = read_synset(pos, static_cast<long>(index->offset[s]), nullptr);
    if (!synset) continue;
    WordSense sense;
    for (int w = 0; w < synset->wcount; ++w) sense.synonyms.push_back(clean(synset->words[w]));
    add_hypernyms(synset, depth, sense.hypernyms);
    if (synset->defn) sense.gloss = synset->defn;
    free_synset(synset);
    out.push_back(std::move(sense));
  }
  free_index(index);
  drain_index(pos);
  return out;
}

std::map<std::string, std::string>& lemma_cache() {
  static std::map<std::string, std::string> cache;
  return cache;
}

}  // namespace

WordNet::WordNet() {
  if (wninit() != 0)
    throw InputError(
        "WordNet: cannot open its database (install Debian's 'wordnet' package, or point WNHOME "
        "or WNSEARCHDIR at a WordNet 3.0 dict folder)");
}

WordNet& WordNet::instance() {
  std::lock_guard<std::mutex> lock(wordnet_mutex());
  static WordNet wordnet;
  return wordnet;
}

std::string WordNet::lemma(const std::string& word) {
  std::lock_guard<std::mutex> lock(wordnet_mutex());
  auto& cache = lemma_cache();
  if (const auto it = cache.find(word); it != cache.end()) return it->second;
  std::string result = word;
  std::vector<char> buf = c_string(word);
  for (int pos : {NOUN, VERB, ADJ})
    if (const char* base = morphstr(buf.data(), pos)) {
      result = clean(base);
      break;
    }
  cache.emplace(word, result);
  return result;
}

bool WordNet::is_noun(const std::string& word) {
  std::lock_guard<std::mutex> lock(wordnet_mutex());
  std::vector<char> buf = c_string(word);
  IndexPtr index = getindex(buf.data(), NOUN);
  if (!index) return false;
  free_index(index);
  drain_index(NOUN);
  return true;
}

std::vector<WordSense> WordNet::senses(const std::string& lemma, int max_senses,
                                       int hypernym_depth) {
  std::lock_guard<std::mutex> lock(wordnet_mutex());
  static std::map<std::tuple<std::string, int, int>, std::vector<WordSense>> cache;
  const auto key = std::make_tuple(lemma, max_senses, hypernym_depth);
  if (const auto it = cache.find(key); it != cache.end()) return it->second;
  std::vector<WordSense> out = read_senses(lemma, NOUN, max_senses, hypernym_depth);
  if (out.empty()) out = read_senses(lemma, VERB, max_senses, hypernym_depth);
  cache.emplace(key, out);
  return out;
}

}  // namespace gslift
