// Read access to Princeton WordNet 3.0 (Debian's wordnet / wordnet-dev: libwordnet and the database
// under /usr/share/wordnet): the lemma of a word form, and a noun's or verb's senses with their
// synonyms, hypernyms and gloss. The C library keeps global state and static buffers, so every call
// holds one process-wide lock, and what was looked up is kept (a word is read from disk once).
#pragma once

#include <string>
#include <vector>

namespace gslift {

struct WordSense {
  std::vector<std::string> synonyms;   // the synset's words, lower case, '_' -> ' '
  std::vector<std::string> hypernyms;  // words of the hypernym synsets, nearest first
  std::string gloss;                   // definition and examples
};

class WordNet {
 public:
  // Opens the database once per process; throws InputError naming WNHOME / WNSEARCHDIR and the
  // package to install when it cannot be read.
  static WordNet& instance();

  // The base form of `word` as a noun, else as a verb, else as an adjective ("lying" -> "lie",
  // "scalpels" -> "scalpel"); `word` itself when WordNet knows none. Lower-case input.
  std::string lemma(const std::string& word);
  // Whether WordNet holds `word` (a lemma, may contain spaces) as a noun.
  bool is_noun(const std::string& word);
  // The first `max_senses` noun senses of `lemma` (verb senses when it has none), with hypernyms
  // up to `hypernym_depth` levels.
  std::vector<WordSense> senses(const std::string& lemma, int max_senses, int hypernym_depth);

 private:
  WordNet();
};

}  // namespace gslift
