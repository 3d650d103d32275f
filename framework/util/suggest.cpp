#include "framework/util/suggest.h"

#include <algorithm>

namespace arcs {

int EditDistance(const std::string& a, const std::string& b) {
  std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const int sub = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string NearestName(const std::string& name, const std::vector<std::string>& candidates) {
  std::string best;
  int best_d = 1 << 30;
  for (const auto& c : candidates) {
    int d = EditDistance(name, c);
    const bool contains = c.find(name) != std::string::npos || name.find(c) != std::string::npos;
    if (contains && std::min(c.size(), name.size()) >= 3) d = std::min(d, 2);
    if (d < best_d) best_d = d, best = c;
  }
  const int limit = std::max<int>(2, static_cast<int>(name.size()) / 3);
  return best_d <= limit ? best : "";
}

std::string DidYouMean(const std::string& name, const std::vector<std::string>& candidates) {
  const std::string near = NearestName(name, candidates);
  return near.empty() ? "" : " (did you mean '" + near + "'?)";
}

}  // namespace arcs
