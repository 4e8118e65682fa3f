// Text-to-instance retrieval (LangOR §1.3 "Retrieval"): the query and every instance's semantics
// are embeddings of one text encoder, so choosing instances is text-to-text cosine similarity.
// Two rules, both plain functions over embeddings:
//  - closed set [decision]: an instance answers query q when q is, of a whole vocabulary of
//    queries, the entry its semantics is most similar to, and q also beats every canonical negative
//    (relevancy > 0.5), so a one-word vocabulary does not select every instance;
//  - open vocabulary (LangSplat): relevancy = min over canonical negatives of
//    softmax(scale [cos_q, cos_neg])[0]; instances above a threshold answer the query.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace gslift {

// LangSplat's canonical negative phrases.
std::vector<std::string> canonical_negatives();

// Per-instance relevancy in [0, 1]: rows of `semantics` (K x E) against `query` (E) and each row
// of `negatives` (M x E): min_j exp(s c_q) / (exp(s c_q) + exp(s c_j)) = min_j 1 / (1 + exp(s
// (c_j - c_q))), c the cosine similarities, s = `scale` (LangSplat: 10). With no negatives every
// relevancy is 1.
Eigen::VectorXf instance_relevancy(const Eigen::MatrixXf& semantics, const Eigen::VectorXf& query,
                                   const Eigen::MatrixXf& negatives, float scale = 10.f);

// Closed-set rule: for each row q of `vocabulary` (Q x E), the instances (rows of `semantics`)
// whose most similar vocabulary entry is q (ties go to the first entry) and whose relevancy to q
// against `negatives` exceeds 0.5. Every instance answers at most one query.
std::vector<std::vector<int>> closed_set_selection(const Eigen::MatrixXf& semantics,
                                                   const Eigen::MatrixXf& vocabulary,
                                                   const Eigen::MatrixXf& negatives,
                                                   float scale = 10.f);

// Open-vocabulary rule: the instances whose relevancy exceeds `threshold`.
std::vector<int> relevancy_selection(const Eigen::VectorXf& relevancy, float threshold);

}  // namespace gslift
