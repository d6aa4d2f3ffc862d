#pragma once
// The solver's loop layer: every loop over the mesh's cells or a sweep's pencils that threads run
// goes through one of these, and the OpenMP pragmas live here only, so that a GPU back-end (or
// another threading model) replaces this file rather than the solver. The bodies are the kernels;
// they see an index (and a pencil's scratch), never a thread.
//
// Scheduling: the work of a cell or a pencil differs by an order of magnitude across a blast deck
// (three materials and mixed cells near the charge, pure air far from it; the sand's strength only
// in the sand) and comes in blocks. Split by count, one thread took the charge's corner of a 3D
// quarter and the other waited a third of each sweep (the V-plate at 30 mm, 2 threads: 13.3 s busy
// against 8.8 s). Each loop therefore keeps what its blocks of iterations cost the last time
// (LoadBalance) and gives each thread a contiguous run of blocks of about equal cost: contiguous, so
// that a thread stays on about the same cells from step to step (handing out chunks as they come,
// OpenMP's dynamic schedule, moved the cells between the cores' caches and cost more than the
// waiting: the 2D one-material benchmark 15.0 -> 11.0 M cell updates/s). Each iteration writes only
// its own cells and books into its own ledger, and the reductions here are minima, so no result
// depends on which thread takes which iteration, nor on the number of threads.
#include <algorithm>
#include <chrono>
#include <cstddef>
#include <limits>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace ejecta::parallel {

// What each block of one loop's iterations cost the last times it ran (seconds), and the threads'
// split that follows from it. Not for two loops at once: a loop writes its costs.
struct LoadBalance {
  std::vector<double> cost;         // s, by block: the mean of the last time and the cost before
  std::vector<std::size_t> begin;   // thread t takes blocks [begin[t], begin[t + 1])
  bool measured = false;            // `cost` holds times (else placeholders)

  // Splits `blocks` blocks among `threads` into contiguous runs of about equal cost (by count the
  // first time, or when the number of blocks changed).
  void plan(std::size_t blocks, int threads) {
    if (cost.size() != blocks) {
      cost.assign(blocks, 1.0);
      measured = false;
    }
    double total = 0.0;
    for (double c : cost) total += c;
    begin.assign(static_cast<std::size_t>(threads) + 1, blocks);
    begin[0] = 0;
    double sum = 0.0;
    std::size_t at = 0;
    for (int t = 1; t < threads; ++t) {
      const double share = total * t / threads;
      while (at < blocks && sum + 0.5 * cost[at] < share) sum += cost[at++];
      begin[static_cast<std::size_t>(t)] = at;
    }
  }

  // Block b's new time, folded into what it cost before: one block slowed by the machine (another
  // process on the core) moves the next split by half as much.
  void record(std::size_t b, double took) { cost[b] = measured ? 0.5 * (cost[b] + took) : took; }
};

// The core of the layer: prepare() once on each thread, then block(b) -> T for each of the thread's
// blocks, each timed into `balance`; returns the least of block()'s results (`none` for none).
template <class T, class Prepare, class Block>
T balancedMin(std::size_t blocks, [[maybe_unused]] bool team, LoadBalance& balance, T none, Prepare&& prepare, Block&& block) {
  T least = none;
#pragma omp parallel if (team)
  {
    int t = 0, threads = 1;
#ifdef _OPENMP
    t = omp_get_thread_num();
    threads = omp_get_num_threads();
#endif
#pragma omp single
    balance.plan(blocks, threads);   // the barrier at its end: every thread sees the plan
    prepare();
    T mine = none;
    const std::size_t to = balance.begin[static_cast<std::size_t>(t) + 1];
    if (threads == 1) {   // nothing to balance: no clock
      for (std::size_t b = 0; b < to; ++b) mine = std::min(mine, block(b));
    } else {
      for (std::size_t b = balance.begin[static_cast<std::size_t>(t)]; b < to; ++b) {
        const auto started = std::chrono::steady_clock::now();
        mine = std::min(mine, block(b));
        balance.record(b, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
      }
    }
#pragma omp critical
    least = std::min(least, mine);
  }
  if (balance.begin.size() > 2) balance.measured = true;   // timed on two threads or more
  return least;
}

// The least of f(i, j, k) over an n0 x n1 x n2 box (+infinity for an empty box), on threads when
// `team`. Blocks are runs of (i, j) rows of at least 512 cells (a clock read costs about 30 ns).
template <class F>
double minOverCells(int n0, int n1, int n2, bool team, LoadBalance& balance, F&& f) {
  const std::size_t rows = static_cast<std::size_t>(n0) * static_cast<std::size_t>(n1), row = static_cast<std::size_t>(std::max(n2, 1));
  const std::size_t per_block = (512 + row - 1) / row, blocks = (rows + per_block - 1) / per_block;
  return balancedMin(
      blocks, team, balance, std::numeric_limits<double>::infinity(), [] {},
      [&f, rows, per_block, n1, n2](std::size_t b) {
        double least = std::numeric_limits<double>::infinity();
        const std::size_t from = b * per_block, to = std::min(rows, from + per_block);
        int i = static_cast<int>(from / static_cast<std::size_t>(n1)), j = static_cast<int>(from % static_cast<std::size_t>(n1));
        for (std::size_t r = from; r < to; ++r) {
          for (int k = 0; k < n2; ++k) {
            const double v = f(i, j, k);
            least = v < least ? v : least;
          }
          if (++j == n1) {
            j = 0;
            ++i;
          }
        }
        return least;
      });
}

// f(b) for blocks b = 0 .. blocks - 1 that the caller cut (a block is worth a clock read: some
// hundreds of cells), on threads when `team`.
template <class F>
void forEachBlock(std::size_t blocks, bool team, LoadBalance& balance, F&& f) {
  balancedMin(blocks, team, balance, 0, [] {}, [&](std::size_t b) {
    f(b);
    return 0;
  });
}

// f(i, j, k) for every cell of an n0 x n1 x n2 box, on threads when `team`.
template <class F>
void forEachCell(int n0, int n1, int n2, bool team, LoadBalance& balance, F&& f) {
  minOverCells(n0, n1, n2, team, balance, [&](int i, int j, int k) {
    f(i, j, k);
    return std::numeric_limits<double>::infinity();
  });
}

// The calling thread's own Scratch, constructed on that thread when it first asks (a thread_local
// declared where only the caller passes would be neither constructed nor destroyed on the team's
// other threads).
template <class Scratch>
Scratch& threadScratch() {
  thread_local Scratch scratch;
  return scratch;
}

// A sweep's pencils, `n_outer` x `n_inner` of them, in tiles of up to `width` neighbouring inner
// indices (the inner index is the one whose neighbours share cache lines: a tile reads each line
// once for all its pencils): f(scratch, outer, inner_from, inner_to) -> std::size_t for each tile,
// with `scratch` a Scratch that each thread keeps from call to call (allocating it every sweep cost
// a 1D run more time in the allocator than in the kernels), prepared by prepare(scratch) once a
// call. A tile is a block of the load balance. Returns the least of f's results (SIZE_MAX for none).
template <class Scratch, class Prepare, class F>
std::size_t forEachTile(int n_outer, int n_inner, int width, bool team, LoadBalance& balance, Prepare&& prepare, F&& f) {
  const int w = std::max(width, 1);
  const std::size_t tiles = static_cast<std::size_t>((n_inner + w - 1) / w);
  return balancedMin(
      static_cast<std::size_t>(n_outer) * tiles, team, balance, std::numeric_limits<std::size_t>::max(),
      [&] { prepare(threadScratch<Scratch>()); },
      [&](std::size_t at) {
        const int from = static_cast<int>(at % tiles) * w;
        return f(threadScratch<Scratch>(), static_cast<int>(at / tiles), from, std::min(from + w, n_inner));
      });
}

}  // namespace ejecta::parallel
