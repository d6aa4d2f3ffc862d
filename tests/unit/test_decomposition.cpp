// A domain split into slabs along axis 0 steps exactly as the whole: the slabs exchange their ghost
// layers, take the smallest time step and sum the body's load in the whole's order, so that every
// field and the load agree bit for bit (the in-process transport, parallel/threads.hpp; MPI ranks
// use the same Exchange interface).
#include <gtest/gtest.h>

#include <cmath>
#include <exception>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "../common/decomposition_case.hpp"
#include "hydro/rezone.hpp"
#include "parallel/exchange.hpp"
#include "parallel/threads.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {
using namespace ejecta;
using hydro::Vec3;
using mesh::Axis;
using mesh::BoundaryKind;

using namespace testcase;

void expectSameCells(const hydro::Solver& whole, const hydro::Solver& slab) {
  const auto& g = slab.grid();
  const int off = g.offset0();
  for (int m = 0; m < whole.materialCount(); ++m) {
    const auto &W = whole.field(m), &B = slab.field(m);
    for (int i = 0; i < g.cells(0); ++i)
      for (int j = 0; j < g.cells(1); ++j) {
        for (int k = 0; k < g.cells(2); ++k) {
        const auto cw = whole.grid().index(i + off, j, k), cb = g.index(i, j, k);
        SCOPED_TRACE(::testing::Message() << "material " << m << " cell " << i + off << "," << j << "," << k << " slab offset " << off);
        ASSERT_EQ(W.alpha[cw], B.alpha[cb]) << "material " << m << " cell " << i + off << "," << j;
        ASSERT_EQ(W.rho[cw], B.rho[cb]);
        ASSERT_EQ(W.e[cw], B.e[cb]);
        ASSERT_EQ(W.h0[cw], B.h0[cb]);
        if (!W.s[0].empty()) {
          for (std::size_t q = 0; q < 6; ++q) ASSERT_EQ(W.s[q][cw], B.s[q][cb]);
        }
        for (int d = 0; d < 3; ++d) ASSERT_EQ(whole.velocity(d)[cw], slab.velocity(d)[cb]);
        }
      }
  }
  const int up = g.dims() == 3 ? 2 : 1;
  ASSERT_EQ(whole.grid().axis(up).faces(), g.axis(up).faces());   // the moved mesh too
}

// Runs `body(r, exchange)` for each of `parts` blocks on a thread of its own (one OpenMP thread
// each), joined by the in-process transport; rethrows the first failure.
void onEachBlock(int parts, const std::function<void(int, parallel::Exchange&)>& body) {
  parallel::ThreadTeam team(parts);
  std::vector<std::exception_ptr> failed(static_cast<std::size_t>(parts));
  std::vector<std::thread> threads;
  for (int r = 0; r < parts; ++r)
    threads.emplace_back([&, r] {
      try {
#ifdef _OPENMP
        omp_set_num_threads(1);
#endif
        body(r, team.member(r));
      } catch (...) {
        failed[static_cast<std::size_t>(r)] = std::current_exception();
      }
    });
  for (auto& t : threads) t.join();
  for (const auto& f : failed)
    if (f) std::rethrow_exception(f);
}

void splitMatchesWhole(int dims, int parts, int steps, bool reuss = false, bool bvd = false) {
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
  auto whole = makeBlock(wholeGrid(dims), reuss, bvd);
  const auto ref = advance(whole, steps);
  const auto slabs = parallel::slabs(wholeGrid(dims).cells(0), parts);
  std::vector<std::unique_ptr<hydro::Solver>> blocks(static_cast<std::size_t>(parts));
  std::vector<Run> runs(static_cast<std::size_t>(parts));
  onEachBlock(parts, [&](int r, parallel::Exchange& ex) {
    const auto ur = static_cast<std::size_t>(r);
    blocks[ur] = std::make_unique<hydro::Solver>(makeBlock(wholeGrid(dims).slab(slabs[ur].begin, slabs[ur].end), reuss, bvd));
    blocks[ur]->setExchange(&ex);
    runs[ur] = advance(*blocks[ur], steps);
  });
  double sum = 0.0;
  for (const double i : ref.impulse) sum += symmetry(whole) * i;
  ASSERT_GT(sum, 10.0);   // N s: the blast has reached the plate, so the test books a real load
  // each slab's energy books are its own: together they are the whole's, to round-off
  double held = 0.0, inflow = 0.0, work = 0.0;
  for (const auto& b : blocks) {
    held += b->totals().total();
    inflow += b->energyLedger().boundary_in;
    work += b->energyLedger().target_work;
  }
  EXPECT_NEAR(held, whole.totals().total(), 1e-12 * whole.totals().total());
  EXPECT_NEAR(inflow, whole.energyLedger().boundary_in, 1e-12 * whole.totals().total());
  EXPECT_NEAR(work, whole.energyLedger().target_work, 1e-12 * whole.totals().total());
  EXPECT_GT(std::abs(work), 0.0);
  // ...and so are their mass books by material (what crossed the boundaries, what was folded)
  const auto& wl = whole.energyLedger();
  for (std::size_t k = 0; k < 3; ++k) {
    double crossed = 0.0, folded = 0.0;
    for (const auto& b : blocks) {
      crossed += b->energyLedger().boundary_mass[k];
      folded += b->energyLedger().folded_mass[k];
    }
    const double scale = whole.totals().mass[k];
    EXPECT_NEAR(crossed, wl.boundary_mass[k], 1e-12 * scale) << k;
    EXPECT_NEAR(folded, wl.folded_mass[k], 1e-12 * scale) << k;
  }
  EXPECT_NE(wl.boundary_mass[0], 0.0);   // some air has crossed the outflow sides: the sums above are not of zeros
  for (int r = 0; r < parts; ++r) {
    EXPECT_EQ(runs[static_cast<std::size_t>(r)].impulse, ref.impulse) << "slab " << r;
    EXPECT_EQ(runs[static_cast<std::size_t>(r)].by_parts, ref.by_parts) << "slab " << r;   // the splits too (10 mm cells, layers to 40 mm)
    expectSameCells(whole, *blocks[static_cast<std::size_t>(r)]);
  }
}

// `ejecta run` on ranks builds each slab as one (no rank holds the whole): the load at rest and the
// early time's map onto the 3D quarter must then be the whole's to the bit, slab by slab.
void slabsBuiltAloneMatchTheWhole(int dims, int parts) {
  const auto whole = makeBlock(wholeGrid(dims));
  const Vec3 at_rest = whole.bodyLoad();
  ASSERT_NE(at_rest[dims == 3 ? 2 : 1], 0.0);
  const auto slabs = parallel::slabs(wholeGrid(dims).cells(0), parts);
  std::vector<Vec3> got(static_cast<std::size_t>(parts));
  onEachBlock(parts, [&](int r, parallel::Exchange& ex) {
    const auto ur = static_cast<std::size_t>(r);
    auto block = makeBlock(wholeGrid(dims).slab(slabs[ur].begin, slabs[ur].end));
    block.setExchange(&ex);
    got[ur] = block.wholeBodyLoad();
  });
  for (int r = 0; r < parts; ++r)
    for (std::size_t d = 0; d < 3; ++d) EXPECT_EQ(got[static_cast<std::size_t>(r)][d], at_rest[d]) << "slab " << r << " axis " << d;
}
TEST(Decomposition, SlabsBuiltAloneTakeTheWholesLoadAtRest) {
  slabsBuiltAloneMatchTheWhole(2, 5);
  slabsBuiltAloneMatchTheWhole(3, 3);
}

// A charge in sand on an (r, z) block of `nr` x `nz` cells over r < 0.12 m, -0.12 < z < 0 m (inside
// the test case's meshes, below its plate), stepped a little: an early time to map.
hydro::Solver earlyBlock(int nr, int nz) {
  hydro::SolverOptions o;
  for (auto& b : o.boundary) b = {BoundaryKind::Reflect, BoundaryKind::Transmit};
  o.detonation.push_back({{0.0, -0.04, 0.0}, 0.0});
  const auto ex = materials::explosive("CompB");
  hydro::Solver src(mesh::Grid(2, mesh::Geometry::Axisymmetric, {Axis::uniform(0.0, 0.12, nr), Axis::uniform(-0.12, 0.0, nz), Axis{}}),
                    {materials::air(), ex, materials::sand(materials::SandInputs::fromWetDensity(1370.0, 0.07))}, o);
  src.paint(0, [](const Vec3&) { return true; }, 1.225, 101325.0 / (0.4 * 1.225));
  src.paint(2, [](const Vec3& x) { return x[1] < -0.01; }, 1370.0, 0.0);
  src.paint(1, [](const Vec3& x) { return x[0] < 0.03 && x[1] > -0.06 && x[1] < -0.02; }, ex.jwl.rho0, ex.jwl.e0 / ex.jwl.rho0);
  for (int n = 0; n < 20; ++n) src.step(src.nextTimeStep(1.0));
  return src;
}

TEST(Decomposition, AnAxisymmetricStateMapsOntoSlabsOfTheQuarterAsOntoTheWhole) {
  const auto src = earlyBlock(12, 12);
  auto whole = makeBlock(wholeGrid(3));
  const auto full = hydro::mapAxisymmetricToQuarter(src, whole);
  const auto slabs = parallel::slabs(wholeGrid(3).cells(0), 3);
  std::size_t cells = 0;
  double heat = 0.0;
  for (const auto& sl : slabs) {
    auto block = makeBlock(wholeGrid(3).slab(sl.begin, sl.end));
    const auto part = hydro::mapAxisymmetricToQuarter(src, block);
    cells += part.target_cells;
    for (const double h : part.heat_by_cell) heat += h;   // in the whole's order: its sum to the bit
    expectSameCells(whole, block);
  }
  EXPECT_EQ(cells, full.target_cells);
  EXPECT_EQ(heat, full.heatJ());
  EXPECT_GT(full.target_cells, 0u);
  EXPECT_GT(full.heatJ(), 0.0);
}

// The same for the nested map of a 2D run (the fine block spans slabs: 12 of the 36 run columns, 5 slabs).
TEST(Decomposition, ANestedStateMapsOntoSlabsAsOntoTheWhole) {
  const auto src = earlyBlock(24, 16);   // 2 x 2 fine cells per run cell (10 x 15 mm)
  auto whole = makeBlock(wholeGrid(2));
  const auto full = hydro::mapNested(src, whole);
  ASSERT_EQ(full.target_cells, 12u * 8u);
  std::size_t cells = 0;
  double heat = 0.0;
  int slabs_mapped = 0;
  for (const auto& sl : parallel::slabs(wholeGrid(2).cells(0), 5)) {
    auto block = makeBlock(wholeGrid(2).slab(sl.begin, sl.end));
    const auto part = hydro::mapNested(src, block);
    cells += part.target_cells;
    slabs_mapped += part.target_cells > 0 ? 1 : 0;
    for (const double h : part.heat_by_cell) heat += h;
    expectSameCells(whole, block);
  }
  EXPECT_EQ(slabs_mapped, 2);
  EXPECT_EQ(cells, full.target_cells);
  EXPECT_EQ(heat, full.heatJ());
}

// Slabs built as slabs and stepped, gathered into a whole on the first block alone (a checkpoint on
// MPI ranks): every cell and the clock of the whole stepped alike.
TEST(Decomposition, SlabsAssembleIntoAWholeOnTheFirstBlock) {
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
  const int parts = 3, steps = 40;
  auto whole = makeBlock(wholeGrid(2));
  (void)advance(whole, steps);
  const auto slabs = parallel::slabs(wholeGrid(2).cells(0), parts);
  auto assembled = makeBlock(wholeGrid(2));   // painted at the start: every cell is overwritten
  onEachBlock(parts, [&](int r, parallel::Exchange& ex) {
    const auto ur = static_cast<std::size_t>(r);
    auto block = makeBlock(wholeGrid(2).slab(slabs[ur].begin, slabs[ur].end));
    block.setExchange(&ex);
    (void)advance(block, steps);
    if (r == 0)
      assembled.assemble(block, ex);
    else
      hydro::Solver::sendForAssembly(block, ex);
  });
  EXPECT_EQ(assembled.time(), whole.time());
  expectSameCells(whole, assembled);
  EXPECT_NEAR(assembled.totals().total(), whole.totals().total(), 1e-14 * whole.totals().total());
}

TEST(Decomposition, SlabsKeepTheWholeGridsGeometryInTheirGhosts) {
  const auto whole = wholeGrid();
  const auto s = whole.slab(12, 24);
  EXPECT_EQ(s.cells(0), 12);
  EXPECT_EQ(s.offset0(), 12);
  for (int i = -mesh::kGhost; i < 12 + mesh::kGhost; ++i) {
    EXPECT_EQ(s.centre(0, i), whole.centre(0, i + 12));
    EXPECT_EQ(s.width(0, i), whole.width(0, i + 12));
  }
  EXPECT_EQ(whole.slab(0, 12).centre(0, -1), whole.centre(0, -1));   // the axis's mirror ghost
  EXPECT_THROW(s.slab(0, 4), InputError);
  EXPECT_THROW(whole.slab(0, 2), InputError);   // fewer cells than ghost layers
}

TEST(Decomposition, TwoSlabsStepBitForBitAsTheWhole) { splitMatchesWhole(2, 2, 150); }
TEST(Decomposition, FiveUnevenSlabsStepBitForBitAsTheWhole) { splitMatchesWhole(2, 5, 150); }
TEST(Decomposition, ThreeSlabsOfA3DVPlateStepBitForBitAsTheWhole) { splitMatchesWhole(3, 3, 60); }
// The Reuss mixture's step reads each cell's neighbours' velocities: the slabs' ghosts, exchanged first
TEST(Decomposition, FiveUnevenSlabsWithTheReussMixtureStepBitForBitAsTheWhole) { splitMatchesWhole(2, 5, 150, true); }
TEST(Decomposition, ThreeSlabsOfA3DVPlateWithTheReussMixtureStepBitForBitAsTheWhole) { splitMatchesWhole(3, 3, 60, true); }
TEST(Decomposition, FiveUnevenSlabsWithThincBvdStepBitForBitAsTheWhole) { splitMatchesWhole(2, 5, 150, false, true); }
TEST(Decomposition, ThreeSlabsOfA3DVPlateWithThincBvdStepBitForBitAsTheWhole) { splitMatchesWhole(3, 3, 60, false, true); }

}  // namespace

// The words of a failure some blocks met reach every block, in rank order, so that all stop and
// one says it (`ejecta run`'s field pieces, the staging folder's check).
TEST(Decomposition, EveryBlockGetsTheOthersFailuresInWordsInRankOrder) {
  const int parts = 3;
  parallel::ThreadTeam team(parts);
  const std::vector<std::string> mine{"", "rank 1: disk full; \"quoted\" \xC3\xA9", "rank 2: no"};
  std::vector<std::string> got(parts), none(parts);
  std::vector<std::thread> threads;
  for (int r = 0; r < parts; ++r)
    threads.emplace_back([&, r] {
      got[static_cast<std::size_t>(r)] = parallel::gatherText(team.member(r), mine[static_cast<std::size_t>(r)]);
      none[static_cast<std::size_t>(r)] = parallel::gatherText(team.member(r), "");
    });
  for (auto& t : threads) t.join();
  for (int r = 0; r < parts; ++r) {
    EXPECT_EQ(got[static_cast<std::size_t>(r)], mine[1] + "; " + mine[2]) << "block " << r;
    EXPECT_EQ(none[static_cast<std::size_t>(r)], "") << "block " << r;
  }
}
