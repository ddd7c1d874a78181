#include <hemivem/support/names.hpp>

#include <algorithm>
#include <cctype>
#include <limits>

namespace hemivem {

std::string to_lower(std::string_view s) {
  std::string r(s);
  std::transform(r.begin(), r.end(), r.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return r;
}

namespace {

std::size_t edit_distance(std::string_view a0, std::string_view b0) {
  const std::string a = to_lower(a0), b = to_lower(b0);
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

}  // namespace

std::string did_you_mean(std::string_view key, const std::vector<std::string>& valid) {
  std::string best;
  std::size_t best_d = std::numeric_limits<std::size_t>::max();
  for (const auto& v : valid) {
    std::size_t d = edit_distance(to_lower(key), to_lower(v));
    const std::string k = to_lower(key), w = to_lower(v);
    if (k.size() >= 2 && (w.rfind(k, 0) == 0 || k.rfind(w, 0) == 0)) d = std::min<std::size_t>(d, 1);
    if (d < best_d) best_d = d, best = v;
  }
  if (best.empty() || best_d > std::max<std::size_t>(2, key.size() / 3)) return {};
  return "; did you mean '" + best + "'?";
}

}  // namespace hemivem
