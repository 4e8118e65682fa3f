// Offline matching of free words onto a vocabulary's classes (issue 30): "ventilator", "nurse" or
// "the person lying on the table" onto anesthesia machine, circulating nurse and patient. Plain
// scoring over words, explainable term by term and deterministic:
//
//  1. Exact: the text, compared without case, spaces or hyphens ("C arm" = "C-arm"), is a class's
//     name or one of its aliases: that class scores 1, every other 0.
//  2. Otherwise the text is split into words; stop words ("the", "a", ...) go, the rest are
//     reduced to WordNet lemmas ("lying" -> "lie"). The words before the first preposition or
//     relative word ("on", "with", "that", ...) are the head phrase, the rest modifiers ("the
//     nurse | walking around", "the table | with the scalpels"); a modifier counts half.
//  3. Each class has weighted terms: the words of its name and aliases (1), their WordNet synonyms
//     (0.8) and direct hypernyms (0.5: surgeon -> doctor), and the lemmas of its description and
//     contexts (0.35; people also get "person"). Each query word expands to itself (1), its WordNet
//     synonyms (0.8), hypernyms up to two levels (0.6) and the words of its first gloss (0.3).
//     A word's match with a class is the best product of an expansion weight and a term weight,
//     over one WordNet hop at most: the word itself against any term, an expansion of it against
//     the class's own words only (else "toaster" -> supporter = assistant would link them). A
//     modifier is matched against the contexts' words only: it says where the thing is or what it
//     is with ("the person lying on the table"), it does not name the class.
//  4. A class's score is the weighted mean of its word matches; when the head phrase names a
//     person (WordNet: a kind of person) object classes are halved, and when it names an artifact
//     people are.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "nodes/scene/vocabulary.hpp"

namespace gslift {

struct LexicalClass {
  std::string name;
  bool person = false;
  std::vector<std::string> exact_keys;  // name and aliases without case, spaces or hyphens
  // lemma -> weight (step 3): the name's, aliases' and contexts' own words; the WordNet synonyms
  // and hypernyms of the name and alias words; the contexts' words alone.
  std::map<std::string, float> terms, wordnet_terms, context_terms;
};

struct LexicalIndex {
  std::vector<LexicalClass> classes;  // in vocabulary order
};

// Reads WordNet (nodes/text/wordnet.hpp) for every class word once.
LexicalIndex build_lexical_index(const Vocabulary& vocabulary);

// One score in [0, 1] per class of the index, in its order.
std::vector<float> lexical_scores(const LexicalIndex& index, const std::string& text);

// Lower-case words of `text` (letters, digits, inner hyphens and apostrophes), without stop words.
std::vector<std::string> content_words(const std::string& text);

}  // namespace gslift
