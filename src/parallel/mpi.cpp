#include "parallel/mpi.hpp"

#include <algorithm>
#include <exception>
#include <string>

#include "core/error.hpp"

namespace ejecta::parallel {
namespace {
void check(int rc, const char* what) {
  if (rc != MPI_SUCCESS) throw RunError(std::string("MPI: ") + what + " failed");
}
int count(std::size_t n) {
  if (n > static_cast<std::size_t>(INT32_MAX)) throw RunError("MPI: a message of more than 2^31 values");
  return static_cast<int>(n);
}
}  // namespace

MpiExchange::MpiExchange(MPI_Comm comm) {
  check(MPI_Comm_dup(comm, &comm_), "MPI_Comm_dup");
  check(MPI_Comm_rank(comm_, &rank_), "MPI_Comm_rank");
  check(MPI_Comm_size(comm_, &size_), "MPI_Comm_size");
}

MpiExchange::~MpiExchange() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized && comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);
}

void MpiExchange::swapHalo(const std::vector<double>& to_lo, const std::vector<double>& to_hi, std::vector<double>& from_lo,
                           std::vector<double>& from_hi) {
  // Each neighbour's halo is as large as the one sent to it (the same layers of the same columns).
  const int lo = rank_ > 0 ? rank_ - 1 : MPI_PROC_NULL, hi = rank_ + 1 < size_ ? rank_ + 1 : MPI_PROC_NULL;
  from_lo.assign(lo == MPI_PROC_NULL ? 0 : to_lo.size(), 0.0);
  from_hi.assign(hi == MPI_PROC_NULL ? 0 : to_hi.size(), 0.0);
  // upward: send to hi, receive from lo; then downward
  check(MPI_Sendrecv(to_hi.data(), hi == MPI_PROC_NULL ? 0 : count(to_hi.size()), MPI_DOUBLE, hi, 1, from_lo.data(), count(from_lo.size()), MPI_DOUBLE,
                     lo, 1, comm_, MPI_STATUS_IGNORE),
        "MPI_Sendrecv");
  check(MPI_Sendrecv(to_lo.data(), lo == MPI_PROC_NULL ? 0 : count(to_lo.size()), MPI_DOUBLE, lo, 2, from_hi.data(), count(from_hi.size()), MPI_DOUBLE,
                     hi, 2, comm_, MPI_STATUS_IGNORE),
        "MPI_Sendrecv");
}

double MpiExchange::minimum(double value) {
  double m = value;
  check(MPI_Allreduce(&value, &m, 1, MPI_DOUBLE, MPI_MIN, comm_), "MPI_Allreduce");
  return m;
}

std::vector<double> MpiExchange::gatherAll(const std::vector<double>& mine) {
  const int n = count(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_), 0);
  check(MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_), "MPI_Allgather");
  std::size_t total = 0;
  for (int r = 0; r < size_; ++r) {
    offsets[static_cast<std::size_t>(r)] = count(total);
    total += static_cast<std::size_t>(counts[static_cast<std::size_t>(r)]);
  }
  std::vector<double> all(total);
  check(MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, comm_), "MPI_Allgatherv");
  return all;
}

void MpiExchange::gatherToFirstEach(const std::vector<double>& mine, const std::function<void(const std::vector<double>&)>& take) {
  const int n = count(mine.size());
  std::vector<int> counts(rank_ == 0 ? static_cast<std::size_t>(size_) : 0);
  check(MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm_), "MPI_Gather");
  // Rank 0 takes one block at a time into one buffer, as large as the largest: every rank learns
  // whether it could allocate it before any data moves, so that all fail together.
  std::vector<double> buffer;
  int ok = 1;
  if (rank_ == 0) {
    try {
      buffer.reserve(static_cast<std::size_t>(*std::max_element(counts.begin(), counts.end())));
    } catch (const std::exception&) {
      ok = 0;
    }
  }
  check(MPI_Bcast(&ok, 1, MPI_INT, 0, comm_), "MPI_Bcast");
  if (!ok) throw RunError("MPI: rank 0 cannot hold the largest block the ranks send it (memory)");
  if (rank_ != 0) {
    check(MPI_Send(mine.data(), n, MPI_DOUBLE, 0, 3, comm_), "MPI_Send");
    return;
  }
  std::exception_ptr failed;
  auto offer = [&](const std::vector<double>& v) {
    if (failed) return;
    try {
      take(v);
    } catch (...) {
      failed = std::current_exception();
    }
  };
  offer(mine);
  for (int r = 1; r < size_; ++r) {   // in rank order, each into the one buffer
    buffer.resize(static_cast<std::size_t>(counts[static_cast<std::size_t>(r)]));
    check(MPI_Recv(buffer.data(), counts[static_cast<std::size_t>(r)], MPI_DOUBLE, r, 3, comm_, MPI_STATUS_IGNORE), "MPI_Recv");
    offer(buffer);
  }
  if (failed) std::rethrow_exception(failed);
}

}  // namespace ejecta::parallel
