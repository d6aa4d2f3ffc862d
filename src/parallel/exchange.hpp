#pragma once
// What a block of the structured mesh needs from the other blocks when the domain is split into
// slabs along axis 0 (one per MPI rank, or per thread in the in-process transport the tests use):
// the ghost layers of its two neighbours, the smallest time step, and everyone's small lists in
// rank order. The solver calls only this interface; the transport (MPI, threads) lives behind it,
// so that the kernels never see MPI.
#include <functional>
#include <string>
#include <vector>

namespace ejecta::parallel {

// Cells [begin, end) of axis 0.
struct Slab {
  int begin = 0, end = 0;
  int cells() const { return end - begin; }
};
// `parts` slabs of `cells` cells, as even as they come (the first ones one cell larger).
std::vector<Slab> slabs(int cells, int parts);

class Exchange {
 public:
  virtual ~Exchange() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Sends `to_lo` to the block below (rank - 1) and `to_hi` to the block above (rank + 1), and
  // returns what they sent this block in `from_lo` / `from_hi` (left empty at the domain's ends).
  virtual void swapHalo(const std::vector<double>& to_lo, const std::vector<double>& to_hi, std::vector<double>& from_lo,
                        std::vector<double>& from_hi) = 0;
  virtual double minimum(double value) = 0;
  // Every block's `mine`, concatenated in rank order, on every block.
  virtual std::vector<double> gatherAll(const std::vector<double>& mine) = 0;
  // Every block's `mine` reaches block 0 alone, one block at a time in rank order (`take` is called
  // there with each, block 0's own first; elsewhere never): what one block assembles, such as the
  // whole's state for a checkpoint, without any block holding every block's copy at once. Block 0
  // says first whether it can take the largest; if not, every block throws RunError together. A
  // `take` that throws still lets the rest arrive (none is left waiting), then rethrows on block 0.
  virtual void gatherToFirstEach(const std::vector<double>& mine, const std::function<void(const std::vector<double>&)>& take) = 0;
};

// Every block's `mine` that is not empty, in rank order, joined by "; ", on every block: the words
// of a failure that some blocks met, for all to stop with and one to say.
std::string gatherText(Exchange& ex, const std::string& mine);

}  // namespace ejecta::parallel
