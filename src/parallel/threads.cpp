#include "parallel/threads.hpp"

#include <algorithm>
#include <exception>

#include "core/error.hpp"

namespace ejecta::parallel {

class ThreadMember final : public Exchange {
 public:
  ThreadMember(ThreadTeam& team, int rank) : team_(team), rank_(rank) {}
  int rank() const override { return rank_; }
  int size() const override { return team_.size_; }
  void swapHalo(const std::vector<double>& to_lo, const std::vector<double>& to_hi, std::vector<double>& from_lo,
                std::vector<double>& from_hi) override {
    const auto r = static_cast<std::size_t>(rank_);
    team_.to_lo_[r] = to_lo;
    team_.to_hi_[r] = to_hi;
    team_.barrier_.arrive_and_wait();   // everyone has posted
    from_lo = rank_ > 0 ? team_.to_hi_[r - 1] : std::vector<double>{};
    from_hi = rank_ + 1 < team_.size_ ? team_.to_lo_[r + 1] : std::vector<double>{};
    team_.barrier_.arrive_and_wait();   // everyone has read
  }
  double minimum(double value) override {
    team_.minima_[static_cast<std::size_t>(rank_)] = value;
    team_.barrier_.arrive_and_wait();
    const double m = *std::min_element(team_.minima_.begin(), team_.minima_.end());
    team_.barrier_.arrive_and_wait();
    return m;
  }
  std::vector<double> gatherAll(const std::vector<double>& mine) override {
    team_.gathered_[static_cast<std::size_t>(rank_)] = mine;
    team_.barrier_.arrive_and_wait();
    std::vector<double> all;
    for (const auto& g : team_.gathered_) all.insert(all.end(), g.begin(), g.end());
    team_.barrier_.arrive_and_wait();
    return all;
  }
  void gatherToFirstEach(const std::vector<double>& mine, const std::function<void(const std::vector<double>&)>& take) override {
    team_.gathered_[static_cast<std::size_t>(rank_)] = mine;
    team_.barrier_.arrive_and_wait();
    std::exception_ptr failed;
    if (rank_ == 0)
      for (const auto& g : team_.gathered_) {
        try {
          if (!failed) take(g);
        } catch (...) {
          failed = std::current_exception();
        }
      }
    team_.barrier_.arrive_and_wait();
    if (failed) std::rethrow_exception(failed);
  }

 private:
  ThreadTeam& team_;
  int rank_;
};

ThreadTeam::ThreadTeam(int size)
    : size_(size), barrier_(size), to_lo_(static_cast<std::size_t>(size)), to_hi_(static_cast<std::size_t>(size)),
      gathered_(static_cast<std::size_t>(size)), minima_(static_cast<std::size_t>(size), 0.0) {
  for (int r = 0; r < size; ++r) members_.push_back(std::make_unique<ThreadMember>(*this, r));
}

}  // namespace ejecta::parallel
