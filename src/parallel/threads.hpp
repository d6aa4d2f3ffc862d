#pragma once
// The in-process transport: N blocks run on N threads of one process and meet at barriers. It
// exists so that the decomposition is tested, bit for bit against the whole domain, on a machine
// without MPI (tests/unit/test_decomposition.cpp).
#include <barrier>
#include <memory>
#include <vector>

#include "parallel/exchange.hpp"

namespace ejecta::parallel {

class ThreadTeam {
 public:
  explicit ThreadTeam(int size);
  int size() const { return size_; }
  // The exchange of block `rank` (one per thread, each used by its own thread only).
  Exchange& member(int rank) { return *members_[static_cast<std::size_t>(rank)]; }

 private:
  friend class ThreadMember;
  int size_;
  std::barrier<> barrier_;
  std::vector<std::vector<double>> to_lo_, to_hi_, gathered_;
  std::vector<double> minima_;
  std::vector<std::unique_ptr<Exchange>> members_;
};

}  // namespace ejecta::parallel
