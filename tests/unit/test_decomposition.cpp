// A domain split into slabs along axis 0 steps exactly as the whole: the slabs exchange their ghost
// layers, take the smallest time step and sum the body's load in the whole's order, so that every
// field and the load agree bit for bit (the in-process transport, parallel/threads.hpp; MPI ranks
// use the same Exchange interface).
#include <gtest/gtest.h>

#include <cmath>
#include <exception>
#include <thread>

#include "core/error.hpp"
#include "hydro/solver.hpp"
#include "materials/material.hpp"
#include "parallel/threads.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {
using namespace ejecta;
using hydro::Vec3;
using mesh::Axis;
using mesh::BoundaryKind;

constexpr double kPi = 3.14159265358979323846;

// A Comp B charge in wet sand under a plate whose underside rises with r (a staircase: faces
// normal to r along its whole width, in every slab), free to rise through the moving mesh, with
// friction and gravity: every path of the sweep that books the body's load.
// In 3D: a quarter (symmetry planes x = 0, y = 0) with a V-shaped plate whose underside rises with
// x, the mesh moving along z.
mesh::Grid wholeGrid(int dims = 2) {
  if (dims == 3)
    return mesh::Grid(3, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 0.24, 12), Axis::uniform(0.0, 0.24, 12), Axis::uniform(-0.12, 0.24, 18)});
  return mesh::Grid(2, mesh::Geometry::Axisymmetric, {Axis::uniform(0.0, 0.36, 36), Axis::uniform(-0.3, 0.3, 40), Axis{}});
}

hydro::Solver makeBlock(const mesh::Grid& grid) {
  const int up = grid.dims() == 3 ? 2 : 1;
  hydro::SolverOptions o;
  o.boundary[0] = {BoundaryKind::Reflect, BoundaryKind::Transmit};
  o.boundary[1] = {BoundaryKind::Reflect, BoundaryKind::Transmit};
  o.boundary[2] = {BoundaryKind::Reflect, BoundaryKind::Transmit};
  o.gravity = {0.0, 0.0, 0.0};
  o.gravity[static_cast<std::size_t>(up)] = -9.81;
  o.body_friction = 0.2;
  o.load_reference_pressure = 101325.0;
  Vec3 det{0.0, 0.0, 0.0};
  det[static_cast<std::size_t>(up)] = -0.04;
  o.detonation.push_back({det, 0.0});
  const auto ex = materials::explosive("CompB");
  hydro::Solver s(grid, {materials::air(), ex, materials::sand(materials::SandInputs::fromWetDensity(1370.0, 0.07))}, o);
  s.paint(0, [](const Vec3&) { return true; }, 1.225, 101325.0 / (0.4 * 1.225));
  // r: the distance from the vertical axis; z: the height
  const auto r = [up](const Vec3& x) { return up == 2 ? std::hypot(x[0], x[1]) : x[0]; };
  const auto z = [up](const Vec3& x) { return x[static_cast<std::size_t>(up)]; };
  s.paint(2, [&](const Vec3& x) { return z(x) < 0.0; }, 1370.0, 0.0);
  s.paint(1, [&](const Vec3& x) { return r(x) < 0.05 && z(x) > -0.06 && z(x) < -0.02; }, ex.jwl.rho0, ex.jwl.e0 / ex.jwl.rho0);
  s.setBody([&](const Vec3& x) { return x[0] < 0.2 && z(x) > 0.005 + 0.25 * x[0] && z(x) < 0.12 + 0.25 * x[0]; });
  s.moveMeshWithBody(up, up == 2 ? -0.1 : -0.25, up == 2 ? 0.24 : 0.3);
  return s;
}

struct Run {
  std::vector<double> impulse;   // the body's vertical impulse of each step
};

// The modelled part of the whole: 2 pi per radian (axisymmetric), 4 quarters (3D).
double symmetry(const hydro::Solver& s) { return s.grid().dims() == 3 ? 4.0 : 2.0 * kPi; }

// Steps `s` as a run does: the time step, the body's velocity from its load (a 50 kg plate).
Run advance(hydro::Solver& s, int steps) {
  const std::size_t up = s.grid().dims() == 3 ? 2 : 1;
  Run r;
  double v = 0.0;
  for (int n = 0; n < steps; ++n) {
    const double dt = s.nextTimeStep(1.0);
    Vec3 w{0.0, 0.0, 0.0};
    w[up] = v;
    s.setBodyVelocity(w);
    s.step(dt);
    r.impulse.push_back(s.lastBodyImpulse()[up]);
    v += symmetry(s) * s.lastBodyImpulse()[up] / 50.0 - 9.81 * dt;
  }
  return r;
}

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

void splitMatchesWhole(int dims, int parts, int steps) {
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
  auto whole = makeBlock(wholeGrid(dims));
  const auto ref = advance(whole, steps);
  const auto slabs = parallel::slabs(wholeGrid(dims).cells(0), parts);
  parallel::ThreadTeam team(parts);
  std::vector<std::unique_ptr<hydro::Solver>> blocks(static_cast<std::size_t>(parts));
  std::vector<Run> runs(static_cast<std::size_t>(parts));
  std::vector<std::exception_ptr> failed(static_cast<std::size_t>(parts));
  std::vector<std::thread> threads;
  for (int r = 0; r < parts; ++r)
    threads.emplace_back([&, r] {
      const auto ur = static_cast<std::size_t>(r);
      try {
#ifdef _OPENMP
        omp_set_num_threads(1);
#endif
        blocks[ur] = std::make_unique<hydro::Solver>(makeBlock(wholeGrid(dims).slab(slabs[ur].begin, slabs[ur].end)));
        blocks[ur]->setExchange(&team.member(r));
        runs[ur] = advance(*blocks[ur], steps);
      } catch (...) {
        failed[ur] = std::current_exception();
      }
    });
  for (auto& t : threads) t.join();
  for (const auto& f : failed)
    if (f) std::rethrow_exception(f);
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
  for (int r = 0; r < parts; ++r) {
    EXPECT_EQ(runs[static_cast<std::size_t>(r)].impulse, ref.impulse) << "slab " << r;
    expectSameCells(whole, *blocks[static_cast<std::size_t>(r)]);
  }
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

}  // namespace
