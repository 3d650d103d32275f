// "Did you mean": the one rule every unknown-name error uses (stage names,
// stage parameters, experiment keys, built-in shapes and curves).
#pragma once

#include <string>
#include <vector>

namespace arcs {

// Edit distance (Levenshtein: insertions, deletions, substitutions).
int EditDistance(const std::string& a, const std::string& b);

// The candidate nearest to `name`, or "" when none is near. Near: an edit
// distance of at most max(2, |name| / 3); a candidate that contains `name`,
// or is contained in it, counts as distance 2 when the shorter of the two has
// at least 3 characters ("rfta" for "rfta2d"). Ties go to the first candidate.
std::string NearestName(const std::string& name, const std::vector<std::string>& candidates);

// " (did you mean 'x'?)" for NearestName's answer, "" when it has none.
std::string DidYouMean(const std::string& name, const std::vector<std::string>& candidates);

}  // namespace arcs
