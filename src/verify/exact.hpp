#pragma once
// Exact and published reference solutions for `ejecta verify`.
#include <vector>

#include "materials/material.hpp"

namespace ejecta::verify {

// Riemann problem for an ideal gas (Toro, "Riemann Solvers and Numerical Methods for Fluid
// Dynamics", ch. 4): density, velocity and pressure at x/t.
struct GasState {
  double rho, u, p;
};
class ExactRiemann {
 public:
  ExactRiemann(GasState left, GasState right, double gamma);
  GasState sample(double xi) const;   // xi = (x - x0) / t
  double starPressure() const { return p_star_; }
  double starVelocity() const { return u_star_; }

 private:
  double f(double p, const GasState& s, double& dfdp) const;
  GasState l_, r_;
  double g_, p_star_ = 0.0, u_star_ = 0.0;
};

// Sedov-Taylor blast wave: shock radius R = (E t^2 / (alpha rho))^(1/(nu+2)), with the energy
// integral alpha of the whole blast (full cylinder per unit length, full sphere) for gamma = 1.4
// (Kamm & Timmes 2007; the values their solver computes: 0.984041 cylindrical, 0.851060
// spherical).
double sedovAlpha(int nu);   // nu = 2 cylindrical, 3 spherical (gamma = 1.4)
double sedovRadius(int nu, double energy, double rho, double t);

// Noh's implosion in cylindrical geometry, gamma = 5/3, unit inflow speed and density.
double nohDensity(double r, double t);

// Free-air peak incident overpressure of a spherical TNT burst (Kinney & Graham, "Explosive
// Shocks in Air", 2nd ed., 1985): Z = R / W^(1/3) in m/kg^(1/3), result in Pa over p_ambient.
double kinneyGrahamOverpressure(double scaled_distance, double p_ambient);

// A piston at speed up driven into sand at rest: the steady shock speed from the Rankine-Hugoniot
// jump of the loading curve plus the plastic deviatoric stress (uniaxial strain).
struct SandShock {
  double shock_speed;   // m/s, relative to the unshocked sand
  double strain;        // - engineering volumetric strain behind the shock
  double stress;        // Pa, axial stress behind the shock
};
SandShock sandPistonShock(const materials::Material& sand, double up);

// Elastic precursor of a uniaxial-strain wave in an elastic-perfectly-plastic solid (linear
// elastic range): Hugoniot elastic limit and longitudinal wave speed.
struct ElasticPrecursor {
  double hel;     // Pa, axial stress at the Hugoniot elastic limit
  double speed;   // m/s, longitudinal elastic wave speed
};
ElasticPrecursor elasticPrecursor(const materials::Material& solid);

// The Taylor wave behind a planar CJ detonation that starts at a rigid wall (x = 0, t = 0):
// pressure at x/t along the JWL isentrope through the CJ point.
class TaylorWave {
 public:
  explicit TaylorWave(const materials::JwlParams& j);
  double pressure(double xi) const;   // xi = x / t
  const materials::CjState& cj() const { return cj_; }

 private:
  materials::CjState cj_;
  std::vector<double> xi_, p_;   // increasing xi
  double p_wall_ = 0.0, xi_wall_ = 0.0;
};

}  // namespace ejecta::verify
