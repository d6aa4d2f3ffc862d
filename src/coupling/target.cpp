#include "coupling/target.hpp"

#include <algorithm>
#include <cmath>

namespace ejecta::coupling {

Target::Target(bool present, bool free, double mass_kg, double gravity_m_s2, double symmetry, int up, const std::vector<std::string>& kinds)
    : present_(present), free_(present && free), mass_(mass_kg), gravity_(gravity_m_s2), symmetry_(symmetry), up_(static_cast<std::size_t>(up)) {
  for (const auto& k : kinds) kind_of_material_.push_back(k == "air" ? 0 : (k == "products" ? 1 : 2));
}

void Target::bookStep(const hydro::Solver& solver, double static_force, double dt, TargetState& st) const {
  const double iz = symmetry_ * solver.lastBodyImpulse()[up_] - static_force * dt;
  st.impulse += iz;
  if (present_)
    for (std::size_t k = 0; k < kind_of_material_.size(); ++k) {
      st.impulse_kind[kind_of_material_[k]] += symmetry_ * solver.lastBodyImpulseByMaterial()[k][up_];
      for (int l = 0; l < hydro::kNearWallDepths; ++l)
        st.impulse_kind_near[3 * static_cast<std::size_t>(l) + kind_of_material_[k]] += symmetry_ * solver.lastBodyImpulseNearWall(l)[k][up_];
    }
  st.impulse_kind[0] -= static_force * dt;   // the load at rest is the air's
  for (int l = 0; l < hydro::kNearWallDepths; ++l) st.impulse_kind_near[3 * static_cast<std::size_t>(l)] -= static_force * dt;
  st.peak_force = std::max(st.peak_force, std::abs(iz / dt));
  if (free_) {
    st.z += st.v * dt;   // the velocity the walls (and the moving mesh) had in this step
    st.v += iz / mass_ - gravity_ * dt;
  }
}

hydro::Vec3 Target::wallVelocity(const TargetState& st) const {
  hydro::Vec3 v{0.0, 0.0, 0.0};
  v[up_] = st.v;
  return v;
}

double Target::lastForce(const hydro::Solver& solver, const TargetState& st) const {
  return solver.lastDt() > 0.0 ? symmetry_ * solver.lastBodyImpulse()[up_] / solver.lastDt() - st.static_force : 0.0;
}

}  // namespace ejecta::coupling
