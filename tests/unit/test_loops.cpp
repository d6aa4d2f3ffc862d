// The loop layer (parallel/loops.hpp): the threads' split by measured cost is contiguous, covers
// every iteration once, and changes no result: a run on 1, 2 or 3 threads gives every field and the
// body's load of every step bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstdint>
#include <vector>

#include "../common/decomposition_case.hpp"
#include "parallel/loops.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {
using namespace ejecta;

TEST(LoadBalance, SplitsIntoContiguousRunsOfAboutEqualCost) {
  parallel::LoadBalance b;
  b.plan(10, 2);   // nothing measured yet: by count
  EXPECT_EQ(b.begin, (std::vector<std::size_t>{0, 5, 10}));
  // the work is at the start (a charge in one corner): the first thread takes fewer blocks
  b.cost = {8, 8, 8, 1, 1, 1, 1, 1, 1, 1};
  b.plan(10, 2);
  EXPECT_EQ(b.begin, (std::vector<std::size_t>{0, 2, 10}));   // 16 against 15
  b.plan(10, 3);
  ASSERT_EQ(b.begin.size(), 4u);
  EXPECT_EQ(b.begin.front(), 0u);
  EXPECT_EQ(b.begin.back(), 10u);
  for (std::size_t t = 0; t + 1 < b.begin.size(); ++t) EXPECT_LE(b.begin[t], b.begin[t + 1]);
  EXPECT_EQ(b.begin[1], 1u);   // a block goes to the third of 31 its middle falls in: 8 | 8 + 8 | 7
  EXPECT_EQ(b.begin[2], 3u);
  b.plan(4, 2);   // another number of blocks: by count again
  EXPECT_EQ(b.cost.size(), 4u);
  EXPECT_EQ(b.begin, (std::vector<std::size_t>{0, 2, 4}));
  b.plan(3, 5);   // more threads than blocks: some take none
  EXPECT_EQ(b.begin.front(), 0u);
  EXPECT_EQ(b.begin.back(), 3u);
}

// The number of OpenMP threads for a scope, restored however the scope ends (a failed ASSERT too).
class ThreadsFor {
 public:
  explicit ThreadsFor([[maybe_unused]] int threads) {
#ifdef _OPENMP
    before_ = omp_get_max_threads();
    omp_set_num_threads(threads);
#endif
  }
  ~ThreadsFor() {
#ifdef _OPENMP
    omp_set_num_threads(before_);
#endif
  }
  ThreadsFor(const ThreadsFor&) = delete;
  ThreadsFor& operator=(const ThreadsFor&) = delete;

 private:
  int before_ = 1;
};

int threadNumber() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

// A scratch whose constructor runs code (counting itself, so that it cannot be constant-initialised
// as Pencil can): each thread's must be built on that thread, and be that thread's alone.
std::atomic<int> g_constructed{0};
struct Scratch {
  Scratch() {
    g_constructed.fetch_add(1);
    tag = 42;
  }
  int tag = 0;
  int owner = -1;
  std::vector<double> data;
};

TEST(LoadBalance, EveryPencilAndCellOnceOnAnyNumberOfThreads) {
  for (int threads : {1, 2, 3}) {
    ThreadsFor use(threads);
    parallel::LoadBalance pencils, cells;
    for (int pass = 0; pass < 3; ++pass) {   // the later passes split by the measured cost
      std::vector<std::atomic<int>> seen(7 * 5);
      const auto least = parallel::forEachTile<Scratch>(
          7, 5, 1, true, pencils,
          [](Scratch& s) {
            s.owner = threadNumber();
            s.data.assign(3, 0.0);
          },
          [&](Scratch& s, int outer, int inner, int inner_to) {
            EXPECT_EQ(inner_to, inner + 1);          // tiles one pencil wide
            EXPECT_EQ(s.tag, 42);                  // constructed on this thread
            EXPECT_EQ(s.owner, threadNumber());    // prepared by this thread: its own
            EXPECT_EQ(s.data.size(), 3u);
            seen[static_cast<std::size_t>(outer * 5 + inner)]++;
            volatile double spin = 0.0;   // uneven work: the low outer indices cost far more
            for (int w = 0; w < (outer < 2 ? 200000 : 100); ++w) spin = spin + 1.0;
            return static_cast<std::size_t>(100 + outer * 5 + inner);
          });
      EXPECT_EQ(least, 100u);
      for (const auto& n : seen) EXPECT_EQ(n.load(), 1) << threads << " threads";
      std::vector<std::atomic<int>> cell(4 * 3 * 2);
      const double m = parallel::minOverCells(4, 3, 2, true, cells, [&](int i, int j, int k) {
        cell[static_cast<std::size_t>((i * 3 + j) * 2 + k)]++;
        return 1.0 + i + 10.0 * j + 100.0 * k;
      });
      EXPECT_EQ(m, 1.0);
      for (const auto& n : cell) EXPECT_EQ(n.load(), 1);
    }
#ifdef _OPENMP
    if (threads > 1) {
      // the costs were measured: the median heavy pencil (outer 0-1) against the median light one
      ASSERT_TRUE(pencils.measured);
      std::vector<double> heavy(pencils.cost.begin(), pencils.cost.begin() + 10), light(pencils.cost.begin() + 10, pencils.cost.end());
      std::nth_element(heavy.begin(), heavy.begin() + 5, heavy.end());
      std::nth_element(light.begin(), light.begin() + 12, light.end());
      EXPECT_GT(heavy[5], 10.0 * light[12]) << threads << " threads";
      EXPECT_LT(pencils.begin[1], 18u);   // the first thread takes fewer pencils than a split by count
    }
#endif
  }
}

// A charge in wet sand under a plate that moves the mesh (2D), and a 3D quarter under a V-plate:
// every field and the load of every step, on 2 and 3 threads against 1.
std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }
std::vector<std::uint64_t> bits(const std::vector<double>& v) {
  std::vector<std::uint64_t> b;
  for (double x : v) b.push_back(bits(x));
  return b;
}

void sameOnAnyThreads(int dims, int steps) {
#ifndef _OPENMP
  GTEST_SKIP() << "built without OpenMP";
#else
  auto one = testcase::makeBlock(testcase::wholeGrid(dims));
  testcase::Run ref;
  {
    ThreadsFor use(1);
    ref = testcase::advance(one, steps);
  }
  for (int threads : {2, 3}) {
    ThreadsFor use(threads);
    auto many = testcase::makeBlock(testcase::wholeGrid(dims));
    const auto run = testcase::advance(many, steps);
    EXPECT_EQ(bits(run.impulse), bits(ref.impulse)) << threads << " threads";
    EXPECT_EQ(bits(run.by_parts), bits(ref.by_parts)) << threads << " threads";
    const std::size_t cells = one.grid().totalCells();
    for (int m = 0; m < one.materialCount(); ++m) {
      const auto& A = one.field(m);
      const auto& B = many.field(m);
      for (std::size_t c = 0; c < cells; ++c) {
        ASSERT_EQ(bits(A.alpha[c]), bits(B.alpha[c])) << threads << " threads, material " << m << ", cell " << c;
        ASSERT_EQ(bits(A.rho[c]), bits(B.rho[c]));
        ASSERT_EQ(bits(A.e[c]), bits(B.e[c]));
        ASSERT_EQ(bits(A.h0[c]), bits(B.h0[c]));
        if (!A.s[0].empty()) {
          for (std::size_t q = 0; q < 6; ++q) ASSERT_EQ(bits(A.s[q][c]), bits(B.s[q][c]));
        }
      }
    }
    for (int d = 0; d < 3; ++d) EXPECT_EQ(bits(one.velocity(d)), bits(many.velocity(d)));
    EXPECT_EQ(bits(one.energyLedger().boundary_in), bits(many.energyLedger().boundary_in));
    EXPECT_EQ(bits(one.energyLedger().target_work), bits(many.energyLedger().target_work));
    EXPECT_EQ(bits(one.stableTimeStep()), bits(many.stableTimeStep()));
  }
#endif
}

// Tiles of neighbouring pencils: every pencil in exactly one tile, tiles never wider than asked,
// the last one of a row the rest, on any number of threads.
TEST(LoadBalance, TilesCoverEveryPencilOnce) {
  for (int threads : {1, 2, 3}) {
    ThreadsFor use(threads);
    parallel::LoadBalance balance;
    for (int width : {1, 3, 8, 20}) {
      std::vector<std::atomic<int>> seen(6 * 11);
      std::atomic<int> tiles{0};
      parallel::forEachTile<Scratch>(6, 11, width, true, balance, [](Scratch&) {}, [&](Scratch&, int outer, int from, int to) {
        EXPECT_LT(from, to);
        EXPECT_LE(to - from, width);
        EXPECT_TRUE(to - from == width || to == 11) << from << " " << to;
        tiles++;
        for (int i = from; i < to; ++i) seen[static_cast<std::size_t>(outer * 11 + i)]++;
        return std::size_t{0};
      });
      for (const auto& n : seen) EXPECT_EQ(n.load(), 1) << width;
      EXPECT_EQ(tiles.load(), 6 * ((11 + width - 1) / width));
    }
  }
}

TEST(LoadBalance, ThreadsChangeNoBitIn2D) { sameOnAnyThreads(2, 120); }
TEST(LoadBalance, ThreadsChangeNoBitIn3D) { sameOnAnyThreads(3, 40); }

}  // namespace
