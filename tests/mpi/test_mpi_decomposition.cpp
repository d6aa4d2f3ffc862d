// The slab decomposition over MPI ranks (parallel/mpi.hpp): every rank steps its slab of the
// decomposition tests' case and, alone, the whole domain; its slab's cells and the body's load of
// every step must equal the whole's bit for bit. Run with any number of ranks (CTest: 2 and 3).
// Exit 0 when every rank agrees, 1 otherwise.
#include <mpi.h>

#include <cstdio>
#include <exception>

#include "../common/decomposition_case.hpp"
#include "parallel/mpi.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {
using namespace ejecta;

// Cells of `slab` that differ from the whole's (every field of every material, the velocity).
long differences(const hydro::Solver& whole, const hydro::Solver& slab) {
  const auto& g = slab.grid();
  long bad = 0;
  for (int m = 0; m < whole.materialCount(); ++m)
    for (int i = 0; i < g.cells(0); ++i)
      for (int j = 0; j < g.cells(1); ++j)
        for (int k = 0; k < g.cells(2); ++k) {
          const auto cw = whole.grid().index(i + g.offset0(), j, k), cb = g.index(i, j, k);
          const auto &W = whole.field(m), &B = slab.field(m);
          bool same = W.alpha[cw] == B.alpha[cb] && W.rho[cw] == B.rho[cb] && W.e[cw] == B.e[cb] && W.h0[cw] == B.h0[cb];
          for (std::size_t q = 0; q < 6 && !W.s[0].empty(); ++q) same = same && W.s[q][cw] == B.s[q][cb];
          for (int d = 0; d < 3; ++d) same = same && whole.velocity(d)[cw] == slab.velocity(d)[cb];
          bad += same ? 0 : 1;
        }
  return bad;
}

int runCase(int dims, int steps, int rank, int size, bool reuss = false) {
  auto whole = testcase::makeBlock(testcase::wholeGrid(dims), reuss);
  const auto ref = testcase::advance(whole, steps);
  parallel::MpiExchange ex(MPI_COMM_WORLD);
  const auto slabs = parallel::slabs(testcase::wholeGrid(dims).cells(0), size);
  const auto& mine = slabs[static_cast<std::size_t>(rank)];
  auto slab = testcase::makeBlock(testcase::wholeGrid(dims).slab(mine.begin, mine.end), reuss);
  slab.setExchange(&ex);
  const auto run = testcase::advance(slab, steps);
  const long bad_cells = differences(whole, slab);
  const bool same_load = run.impulse == ref.impulse && run.by_parts == ref.by_parts;   // the total and its splits
  double load = 0.0;
  for (const double i : ref.impulse) load += testcase::symmetry(whole) * i;
  std::printf("%dD%s, rank %d of %d, cells %d..%d: %ld cells differ, load %s the whole's (%.6g N s over %d steps)\n", dims,
              reuss ? " (Reuss mixture)" : "", rank, size, mine.begin, mine.end, bad_cells, same_load ? "equals" : "DIFFERS from", load, steps);
  return bad_cells == 0 && same_load && load > 10.0 ? 0 : 1;
}
}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int failed = 0;
  try {
    // the Reuss mixture's step reads its neighbours' velocities across the slabs' cut
    failed = runCase(2, 150, rank, size) | runCase(3, 60, rank, size) | runCase(2, 150, rank, size, true);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rank %d: %s\n", rank, e.what());
    MPI_Abort(MPI_COMM_WORLD, 2);
  }
  int any = 0;
  MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return any;
}
