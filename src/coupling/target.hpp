#pragma once
// The rigid target's side of the coupling between the flow and the target: what each step of the
// flow gives it (net of the load at rest), split by material kind, and a free target's equation of
// motion, m dv/dt = F - m g. The flow's side (the wall faces, the moving mesh) is the solver's
// (hydro/solver.hpp: setBody, moveMeshWithBody); the run driver only connects the two.
#include <string>
#include <vector>

#include "hydro/solver.hpp"

namespace ejecta::coupling {

// What a target accumulates over a run (a checkpoint holds it).
struct TargetState {
  double z = 0.0, v = 0.0;                     // m, m/s: its underside's height, its vertical velocity
  double impulse = 0.0, peak_force = 0.0;      // N s, N: the blast's, on the whole target
  std::vector<double> impulse_kind{0.0, 0.0, 0.0};   // N s by the material beside each face: air, products, soil
  // N s by the materials within hydro::kNearWallDepth_m[l] of each face: [3 l + kind]
  std::vector<double> impulse_kind_near = std::vector<double>(3 * hydro::kNearWallDepths, 0.0);
  bool static_known = false;
  double static_force = 0.0;                   // N, the load at rest (taken off the blast's)
};

class Target {
 public:
  // `kinds`: each material's kind ("air", "products" or "soil"); `symmetry`: modelled part -> whole
  // (2 pi per radian, 4 for a quarter); `up`: the vertical axis; `free`: it moves (mass_kg > 0).
  Target(bool present, bool free, double mass_kg, double gravity_m_s2, double symmetry, int up, const std::vector<std::string>& kinds);

  // Books one step of `solver` (the run's or the early time's fine block's) into `st`, with
  // `static_force` the load at rest on the target's part on that solver's mesh.
  void bookStep(const hydro::Solver& solver, double static_force, double dt, TargetState& st) const;
  // The velocity the flow's walls take for the next step.
  hydro::Vec3 wallVelocity(const TargetState& st) const;
  // The force of the last step, N, net of the load at rest (0 before any step).
  double lastForce(const hydro::Solver& solver, const TargetState& st) const;
  bool present() const { return present_; }

 private:
  bool present_, free_;
  double mass_, gravity_, symmetry_;
  std::size_t up_;
  std::vector<std::size_t> kind_of_material_;   // index into TargetState::impulse_kind
};

}  // namespace ejecta::coupling
