#include "parallel/exchange.hpp"

#include "core/error.hpp"

namespace ejecta::parallel {

std::vector<Slab> slabs(int cells, int parts) {
  if (parts < 1 || cells < parts) throw InputError("ranks", "cannot split " + std::to_string(cells) + " cells into " + std::to_string(parts) + " slabs");
  std::vector<Slab> s;
  int at = 0;
  for (int r = 0; r < parts; ++r) {
    const int n = cells / parts + (r < cells % parts ? 1 : 0);
    s.push_back({at, at + n});
    at += n;
  }
  return s;
}

std::string gatherText(Exchange& ex, const std::string& mine) {
  // each block's text as [length, characters...], one double a character
  std::vector<double> packed{static_cast<double>(mine.size())};
  for (const unsigned char ch : mine) packed.push_back(static_cast<double>(ch));
  const auto all = ex.gatherAll(packed);
  std::string joined;
  for (std::size_t at = 0; at < all.size();) {
    const auto n = static_cast<std::size_t>(all[at++]);
    if (n == 0) continue;
    if (!joined.empty()) joined += "; ";
    for (std::size_t i = 0; i < n; ++i) joined += static_cast<char>(static_cast<unsigned char>(all[at + i]));
    at += n;
  }
  return joined;
}

}  // namespace ejecta::parallel
