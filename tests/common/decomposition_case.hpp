#pragma once
// The decomposition tests' case (tests/unit/test_decomposition.cpp with threads,
// tests/mpi/test_mpi_decomposition.cpp with MPI ranks): a Comp B charge in wet sand under a free
// plate whose underside rises with x (a staircase: faces normal to axis 0 in every slab), the mesh
// moving with it, friction and gravity: every path of the sweep that books the body's load.
#include <cmath>
#include <vector>

#include "hydro/solver.hpp"
#include "materials/material.hpp"

namespace ejecta::testcase {
using hydro::Vec3;
using mesh::Axis;
using mesh::BoundaryKind;

constexpr double kPi = 3.14159265358979323846;

// A Comp B charge in wet sand under a plate whose underside rises with r (a staircase: faces
// normal to r along its whole width, in every slab), free to rise through the moving mesh, with
// friction and gravity: every path of the sweep that books the body's load.
// In 3D: a quarter (symmetry planes x = 0, y = 0) with a V-shaped plate whose underside rises with
// x, the mesh moving along z.
inline mesh::Grid wholeGrid(int dims = 2) {
  if (dims == 3)
    return mesh::Grid(3, mesh::Geometry::Cartesian, {Axis::uniform(0.0, 0.24, 12), Axis::uniform(0.0, 0.24, 12), Axis::uniform(-0.12, 0.24, 18)});
  return mesh::Grid(2, mesh::Geometry::Axisymmetric, {Axis::uniform(0.0, 0.36, 36), Axis::uniform(-0.3, 0.3, 40), Axis{}});
}

// reuss: SolverOptions::mixture_reuss (the step then reads its neighbours' velocities); bvd:
// SolverOptions::thinc_bvd (the remap then reads two cells past each donor).
inline hydro::Solver makeBlock(const mesh::Grid& grid, bool reuss = false, bool bvd = false) {
  const int up = grid.dims() == 3 ? 2 : 1;
  hydro::SolverOptions o;
  o.boundary[0] = {BoundaryKind::Reflect, BoundaryKind::Transmit};
  o.boundary[1] = {BoundaryKind::Reflect, BoundaryKind::Transmit};
  o.boundary[2] = {BoundaryKind::Reflect, BoundaryKind::Transmit};
  o.gravity = {0.0, 0.0, 0.0};
  o.gravity[static_cast<std::size_t>(up)] = -9.81;
  o.body_friction = 0.2;
  o.mixture_reuss = reuss;
  o.thinc_bvd = bvd;
  o.load_reference_pressure = 101325.0;
  o.inflow_barred = {1};   // as a run's: the outflow sides let no products back in
  o.inflow_fill = 0;
  o.inflow_fill_rho = 1.225;
  o.inflow_fill_p = 101325.0;
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
  std::vector<double> impulse;    // the body's vertical impulse of each step
  std::vector<double> by_parts;   // ...by material, and by material within each depth of the wall (every step)
};

// The modelled part of the whole: 2 pi per radian (axisymmetric), 4 quarters (3D).
inline double symmetry(const hydro::Solver& s) { return s.grid().dims() == 3 ? 4.0 : 2.0 * kPi; }

// Steps `s` as a run does: the time step, the body's velocity from its load (a 50 kg plate).
inline Run advance(hydro::Solver& s, int steps) {
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
    for (std::size_t k = 0; k < static_cast<std::size_t>(s.materialCount()); ++k) {
      r.by_parts.push_back(s.lastBodyImpulseByMaterial()[k][up]);
      for (int l = 0; l < hydro::kNearWallDepths; ++l) r.by_parts.push_back(s.lastBodyImpulseNearWall(l)[k][up]);
    }
    v += symmetry(s) * s.lastBodyImpulse()[up] / 50.0 - 9.81 * dt;
  }
  return r;
}

}  // namespace ejecta::testcase
