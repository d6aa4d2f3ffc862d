#pragma once
// The MPI transport of the slab decomposition (parallel/exchange.hpp): rank r owns slab r of the
// domain along axis 0. Built only with EJECTA_MPI (Open MPI); everything above it sees Exchange.
#include <mpi.h>

#include "parallel/exchange.hpp"

namespace ejecta::parallel {

class MpiExchange final : public Exchange {
 public:
  explicit MpiExchange(MPI_Comm comm);   // duplicates `comm`: the solver's messages never meet the caller's
  ~MpiExchange() override;
  MpiExchange(const MpiExchange&) = delete;
  MpiExchange& operator=(const MpiExchange&) = delete;
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  void swapHalo(const std::vector<double>& to_lo, const std::vector<double>& to_hi, std::vector<double>& from_lo,
                std::vector<double>& from_hi) override;
  double minimum(double value) override;
  std::vector<double> gatherAll(const std::vector<double>& mine) override;
  void gatherToFirstEach(const std::vector<double>& mine, const std::function<void(const std::vector<double>&)>& take) override;

 private:
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1;
};

}  // namespace ejecta::parallel
