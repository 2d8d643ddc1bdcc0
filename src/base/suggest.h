// "Did you mean ...?" for misspelt commands and options: the nearest known word by edit
// distance, when it is near enough to be a typo rather than a different word.
#pragma once

#include <string>
#include <vector>

namespace veil {

// Levenshtein distance (insertions, deletions and substitutions of one byte each cost 1).
std::size_t editDistance(const std::string& a, const std::string& b);

// The candidate nearest to `word` if its distance is at most max(1, |word| / 3) (so "rendr"
// finds "render", "--widht" finds "--width", "foo" finds nothing); empty otherwise. Ties go
// to the first candidate.
std::string nearestWord(const std::string& word, const std::vector<std::string>& candidates);

// " (did you mean 'NAME'?)" for nearestWord's answer; empty when there is none.
std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates);

} // namespace veil
