#include "nodes/text/lexical_matcher.hpp"

#include <algorithm>
#include <cctype>
#include <set>

#include "nodes/text/wordnet.hpp"

namespace gslift {
namespace {

// Term weights of a class (step 3 of the header) and expansion weights of a query word.
constexpr float kNameTerm = 1.f, kSynonymTerm = 0.8f, kHypernymTerm = 0.5f, kContextTerm = 0.35f;
constexpr float kSelf = 1.f, kSynonym = 0.8f, kHypernym = 0.6f, kGloss = 0.3f;
constexpr float kModifier = 0.5f;   // weight of a word after the head phrase
constexpr float kOtherKind = 0.5f;  // factor on classes of the other kind (person / object)
constexpr int kSenses = 2;          // WordNet senses read per word (most frequent first)
constexpr int kKindDepth = 10;      // hypernym levels searched for "person" / "artifact"

const std::set<std::string>& stop_words() {
  static const std::set<std::string> words{
      "a",     "an",    "the",  "this", "that's", "these", "those", "is",   "are", "be",
      "being", "been",  "it",   "its",  "one",    "ones",  "some",  "any",  "and", "or",
      "to",    "there", "here", "all",  "very",   "just",  "thing", "who's"};
  return words;
}

const std::set<std::string>& articles() {
  static const std::set<std::string> words{"a", "an", "the"};
  return words;
}

// Words that end the head phrase: prepositions and relative words.
const std::set<std::string>& break_words() {
  static const std::set<std::string> words{
      "on",     "in",      "at",    "of",      "with",   "without", "by",     "for",  "from",
      "above",  "over",    "under", "below",   "near",   "beside",  "behind", "next", "around",
      "that",   "which",   "who",   "whose",   "where",  "while",   "into",   "onto", "between",
      "across", "against", "along", "beneath", "toward", "towards", "during"};
  return words;
}

std::string exact_key(const std::string& text) {
  std::string key;
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (std::isalnum(c) || c >= 0x80) key.push_back(static_cast<char>(std::tolower(c)));
  }
  return key;
}

// All lower-case words, stop words included (the break words are needed for the head phrase).
std::vector<std::string> all_words(const std::string& text) {
  std::vector<std::string> words;
  std::string current;
  auto flush = [&] {
    while (!current.empty() && (current.back() == '-' || current.back() == '\''))
      current.pop_back();
    if (current.size() > 2 && current.compare(current.size() - 2, 2, "'s") == 0)
      current.resize(current.size() - 2);
    if (!current.empty()) words.push_back(current);
    current.clear();
  };
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (std::isalnum(c) || c >= 0x80 || ((ch == '-' || ch == '\'') && !current.empty()))
      current.push_back(static_cast<char>(std::tolower(c)));
    else
      flush();
  }
  flush();
  return words;
}

void raise(std::map<std::string, float>& terms, const std::string& term, float weight) {
  float& w = terms[term];
  w = std::max(w, weight);
}

// A word of a class name or alias, and the hyphen-free parts of a hyphenated one ("c-arm").
void add_name_word(LexicalClass& c, const std::string& word) {
  WordNet& wn = WordNet::instance();
  const std::string lemma = wn.lemma(word);
  raise(c.terms, lemma, kNameTerm);
  for (const WordSense& sense : wn.senses(lemma, kSenses, 2)) {
    for (const std::string& s : sense.synonyms)
      if (s.find(' ') == std::string::npos) raise(c.wordnet_terms, s, kSynonymTerm);
    for (const std::string& h : sense.hypernyms)
      if (h.find(' ') == std::string::npos) raise(c.wordnet_terms, h, kHypernymTerm);
  }
}

float lookup(const std::map<std::string, float>& terms, const std::string& term) {
  const auto it = terms.find(term);
  return it == terms.end() ? 0.f : it->second;
}

// Query word -> (expansion, weight), step 3.
std::map<std::string, float> expansions(const std::string& lemma) {
  std::map<std::string, float> out;
  raise(out, lemma, kSelf);
  const std::vector<WordSense> senses = WordNet::instance().senses(lemma, kSenses, 2);
  for (const WordSense& sense : senses) {
    for (const std::string& s : sense.synonyms) raise(out, s, kSynonym);
    for (const std::string& h : sense.hypernyms) raise(out, h, kHypernym);
  }
  // Gloss words as written and without a plural s: lemmatising each through WordNet would cost
  // more than the rest of the query.
  if (!senses.empty())
    for (const std::string& g : content_words(senses.front().gloss)) {
      raise(out, g, kGloss);
      if (g.size() > 3 && g.back() == 's') raise(out, g.substr(0, g.size() - 1), kGloss);
    }
  return out;
}

// Whether the first sense of `lemma` is a kind of `ancestor` (WordNet hypernym closure).
bool kind_of(const std::string& lemma, const std::string& ancestor) {
  if (lemma == ancestor) return true;
  const std::vector<WordSense> senses = WordNet::instance().senses(lemma, 1, kKindDepth);
  if (senses.empty()) return false;
  const auto& h = senses.front().hypernyms;
  return std::find(h.begin(), h.end(), ancestor) != h.end();
}

}  // namespace

std::vector<std::string> content_words(const std::string& text) {
  std::vector<std::string> out;
  for (std::string& w : all_words(text))
    if (!stop_words().count(w) && !break_words().count(w)) out.push_back(std::move(w));
  return out;
}

LexicalIndex build_lexical_index(const Vocabulary& vocabulary) {
  WordNet& wn = WordNet::instance();
  LexicalIndex index;
  for (const EntityContext& e : vocabulary.entities) {
    LexicalClass c;
    c.name = e.name;
    c.person = e.person;
    std::vector<std::string> names = e.aliases;
    names.insert(names.begin(), e.name);
    for (const std::string& context : {e.spatial, e.behaviour, e.appearance, e.description})
      for (const std::string& w : content_words(context))
        raise(c.context_terms, wn.lemma(w), kContextTerm);
    if (e.person) raise(c.context_terms, "person", kContextTerm);
    c.terms = c.context_terms;
    for (const std::string& n : names) {
      c.exact_keys.push_back(exact_key(n));
      for (const std::string& w : content_words(n)) {
        add_name_word(c, w);
        if (w.find('-') != std::string::npos) {
          std::string part;
          for (const char ch : w + "-")
            if (ch != '-') {
              part.push_back(ch);
            } else if (!part.empty()) {
              add_name_word(c, part);
              part.clear();
            }
        }
      }
    }
    index.classes.push_back(std::move(c));
  }
  return index;
}

std::vector<float> lexical_scores(const LexicalIndex& index, const std::string& text) {
  const size_t k_count = index.classes.size();
  std::vector<float> scores(k_count, 0.f);
  const std::string key = exact_key(text);
  for (size_t k = 0; k < k_count; ++k) {
    const auto& keys = index.classes[k].exact_keys;
    if (!key.empty() && std::find(keys.begin(), keys.end(), key) != keys.end()) {
      scores[k] = 1.f;
      return scores;
    }
  }
  WordNet& wn = WordNet::instance();
  bool in_head = true, head_person = false, head_artifact = false;
  float total_weight = 0;
  for (const std::string& word : all_words(text)) {
    if (break_words().count(word)) {
      in_head = in_head && total_weight == 0;  // a leading "on ..." has no head yet
      continue;
    }
    // An article after head words opens a clause: "the table | the patient lies on".
    if (articles().count(word) && total_weight > 0) in_head = false;
    if (stop_words().count(word)) continue;
    const std::string lemma = wn.lemma(word);
    const float weight = in_head ? 1.f : kModifier;
    if (in_head) {
      head_person = head_person || kind_of(lemma, "person");
      head_artifact = head_artifact || kind_of(lemma, "artifact");
    }
    const std::map<std::string, float> expanded = expansions(lemma);
    for (size_t k = 0; k < k_count; ++k) {
      const LexicalClass& c = index.classes[k];
      const auto& own = in_head ? c.terms : c.context_terms;
      float best = std::max(lookup(own, lemma), in_head ? lookup(c.wordnet_terms, lemma) : 0.f);
      for (const auto& [term, w] : expanded) best = std::max(best, w * lookup(own, term));
      scores[k] += weight * best;
    }
    total_weight += weight;
  }
  if (total_weight == 0) return scores;
  for (size_t k = 0; k < k_count; ++k) {
    scores[k] /= total_weight;
    const bool person = index.classes[k].person;
    if ((head_person && !head_artifact && !person) || (head_artifact && !head_person && person))
      scores[k] *= kOtherKind;
  }
  return scores;
}

}  // namespace gslift
