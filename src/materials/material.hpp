#pragma once
// Materials of the Eulerian solver behind one interface: an equation of state (ideal gas, JWL
// detonation products with programmed burn, Mie-Gruneisen, the two-input sand model) and a
// strength model (none, von Mises elastic-perfectly-plastic, the sand's pseudo-tensor yield vs
// pressure). The solver switches on the kind once per batch of cells; evaluation is a small
// inline function with no allocation. SI units: kg/m3, J/kg, Pa, m/s.
#include <cstddef>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "materials/sand_model.hpp"

namespace ejecta::materials {

enum class EosKind { IdealGas, Jwl, MieGruneisen, Sand };
enum class StrengthKind { None, VonMises, PseudoTensor };

struct IdealGasParams {
  double gamma = 1.4;   // -
};

// JWL products, LLNL form: p = A(1 - w/(R1 V))e^(-R1 V) + B(1 - w/(R2 V))e^(-R2 V) + w rho e with
// V = rho0/rho; the charge starts at rho0 with specific energy E0/rho0. Programmed burn: a cell
// lights at t_L = distance / D from the nearest detonation point and its pressure is scaled by a
// burn fraction that rises from 0 to 1 over `burn_width` cells.
struct JwlParams {
  double rho0 = 1630.0;   // kg/m3
  double a = 371.2e9, b = 3.231e9;   // Pa
  double r1 = 4.15, r2 = 0.95, omega = 0.30;
  double e0 = 7.0e9;      // Pa (J/m3 of unreacted explosive)
  double d_cj = 6930.0;   // m/s
  double p_cj = 21.0e9;   // Pa, handbook value (for reports)
  double burn_width = 2.0;   // cells
};

// Linear Us-up Hugoniot reference (LS-DYNA *EOS_GRUNEISEN, a = 0):
// p = rho0 C^2 mu [1 + (1 - g0/2) mu] / [1 - (S1 - 1) mu]^2 + g0 rho0 e  (mu = rho/rho0 - 1 > 0),
// p = rho0 C^2 mu + g0 rho0 e in tension, and never below p_min.
struct MieGruneisenParams {
  double rho0 = 1000.0, c0 = 1500.0, s1 = 1.75, gamma0 = 0.28;
  double p_min = -1.0e5;   // Pa, cavitation / spall limit
};

struct StrengthParams {
  StrengthKind kind = StrengthKind::None;
  double shear_modulus = 0.0;   // Pa (von Mises); the sand's comes from its model
  double yield = 0.0;           // Pa, von Mises flow stress
};

struct Material {
  std::string name;
  EosKind eos = EosKind::IdealGas;
  IdealGasParams gas{};
  JwlParams jwl{};
  MieGruneisenParams mg{};
  std::shared_ptr<const SandModel> sand_model;
  std::shared_ptr<const SandPointEos> sand;
  double sand_slope = 0.0, sand_plateau = 0.0;   // pseudo-tensor yield: min(slope p, plateau)
  StrengthParams strength{};

  double referenceDensity() const;
  bool hasStrength() const { return strength.kind != StrengthKind::None; }
  void validate() const;   // throws InputError naming the parameter and its range
};

Material idealGas(std::string name, double gamma);
Material air();   // gamma 1.4 (shared/data/constituents.csv)
Material explosive(const std::string& name);   // "C4", "CompB", "TNT": shared/data/explosives_jwl.csv
Material water();
Material steel();   // mild/armour steel, Mie-Gruneisen + von Mises (values documented in material.cpp)
Material sand(const SandInputs& inputs, const std::string& name = "sand");

// Thermodynamic state of one material in one cell, as the hydro kernels need it.
struct EosState {
  double pressure;   // Pa
  double bulk;       // Pa, rho c^2 (>= a small floor: used for the time step and impedances)
};

// Pressure and stiffness of material m at density rho and specific internal energy e. `h0` is the
// material's history scalar: burn fraction (JWL) or largest natural strain reached (sand).
inline EosState evaluateEos(const Material& m, double rho, double e, double h0) noexcept {
  switch (m.eos) {
    case EosKind::IdealGas: {
      const double p = (m.gas.gamma - 1.0) * rho * (e > 0.0 ? e : 0.0);
      return {p, m.gas.gamma * p + 1e-6};
    }
    case EosKind::Jwl: {
      const auto& j = m.jwl;
      const double v = j.rho0 / rho;
      // exp(-x) is +0 in double beyond x = 745.2: taken without the call, whose underflow path
      // (products expanded 250-fold and more, a large part of a late run) is slow; the same +0
      const auto decay = [](double x) { return x > 750.0 ? 0.0 : std::exp(-x); };
      const double e1 = j.a * decay(j.r1 * v), e2 = j.b * decay(j.r2 * v);
      const double w = j.omega;
      const double p = e1 * (1.0 - w / (j.r1 * v)) + e2 * (1.0 - w / (j.r2 * v)) + w * rho * e;
      // dp/drho at constant e, via dV/drho = -V/rho.
      const double dpdv = e1 * (-j.r1 * (1.0 - w / (j.r1 * v)) + w / (j.r1 * v * v)) +
                          e2 * (-j.r2 * (1.0 - w / (j.r2 * v)) + w / (j.r2 * v * v));
      const double dpdrho = -dpdv * v / rho + w * e;
      double bulk = rho * dpdrho + w * p;   // rho c^2 = rho dp/drho|e + (p/rho) dp/de|rho
      bulk = bulk > 1e5 ? bulk : 1e5;
      // Products carry no tension: a sliver driven below zero pressure (by the errors of a mixed
      // cell) would otherwise pull on everything around it.
      const double f = h0;
      return {p > 0.0 ? f * p : 0.0, bulk};
    }
    case EosKind::MieGruneisen: {
      const auto& g = m.mg;
      const double mu = rho / g.rho0 - 1.0;
      const double k0 = g.rho0 * g.c0 * g.c0;
      double ph, dph;
      if (mu > 0.0) {
        const double num = k0 * mu * (1.0 + (1.0 - 0.5 * g.gamma0) * mu);
        const double den = 1.0 - (g.s1 - 1.0) * mu;
        ph = num / (den * den);
        const double dnum = k0 * (1.0 + 2.0 * (1.0 - 0.5 * g.gamma0) * mu);
        dph = dnum / (den * den) + 2.0 * num * (g.s1 - 1.0) / (den * den * den);
      } else {
        ph = k0 * mu;
        dph = k0;
      }
      double p = ph + g.gamma0 * g.rho0 * e;
      p = p > g.p_min ? p : g.p_min;
      double bulk = rho * dph / g.rho0 + g.gamma0 * g.rho0 * p / rho;
      bulk = bulk > 0.01 * k0 ? bulk : 0.01 * k0;
      return {p, bulk};
    }
    case EosKind::Sand: {
      const double x = std::log(rho / m.sand->referenceDensity());
      const auto r = m.sand->evaluate(x, h0, e);
      return {r.pressure, r.bulk_modulus};
    }
  }
  return {0.0, 1e5};
}

// The lowest pressure the material can carry, Pa: 0 for gases and detonation products, the spall
// limit of a Mie-Gruneisen solid, the sand's tension cutoff. A wall cannot pull on it harder.
inline double tensionLimit(const Material& m) noexcept {
  switch (m.eos) {
    case EosKind::MieGruneisen: return m.mg.p_min;
    case EosKind::Sand: return m.sand->tensionCutoff();
    case EosKind::IdealGas:
    case EosKind::Jwl: return 0.0;
  }
  return 0.0;
}

// The history scalar after a cell holds the material at density rho: the sand's largest natural
// strain ln(rho/rho0) grows (it sets the unloading branch and the shear modulus); the burn
// fraction of products is the burn's to change.
inline double updatedHistory(const Material& m, double rho, double h0) noexcept {
  if (m.eos != EosKind::Sand) return h0;
  const double x = std::log(rho / m.sand->referenceDensity());
  return x > h0 ? x : h0;
}

// evaluateEos and updatedHistory together: the sand's natural strain ln(rho/rho0) taken once
// (the same numbers to the bit; the gather asks for both in every cell the material is in).
inline EosState evaluateEosAndHistory(const Material& m, double rho, double e, double h0, double& history) noexcept {
  if (m.eos != EosKind::Sand) {
    history = h0;
    return evaluateEos(m, rho, e, h0);
  }
  const double x = std::log(rho / m.sand->referenceDensity());
  history = x > h0 ? x : h0;
  const auto r = m.sand->evaluate(x, h0, e);
  return {r.pressure, r.bulk_modulus};
}

// evaluateEosAndHistory over cells 0 .. n-1 where the fraction `alpha` is above zero; elsewhere
// pressure, bulk and history are 0. `history` holds h0 on entry and the history on return. The
// kind is switched on once for the batch; the same numbers as the call per cell.
void evaluateEosAndHistory(const Material& m, std::ptrdiff_t n, const double* alpha, const double* rho, const double* e, double* history,
                           double* pressure, double* bulk) noexcept;

// Shear modulus (Pa) for the history h0 and the pressure p now, and yield strength (Pa) at pressure
// p, for materials with strength.
inline double shearModulus(const Material& m, double h0, double p) noexcept {
  return m.strength.kind == StrengthKind::VonMises ? m.strength.shear_modulus : (m.sand ? m.sand->shearModulus(h0, p) : 0.0);
}
inline double yieldStrength(const Material& m, double p) noexcept {
  if (m.strength.kind == StrengthKind::VonMises) return m.strength.yield;
  // the pseudo-tensor: friction on the effective stress (the pore air's pressure carries no shear), then the plateau
  const double pe = m.sand ? p - m.sand->porePressure() : p;
  const double y = m.sand_slope * (pe > 0.0 ? pe : 0.0);
  return y < m.sand_plateau ? y : m.sand_plateau;
}

// The CJ state implied by a JWL set: the products' Hugoniot from (rho0, p = 0, E0) and the
// Rayleigh line tangent to it. Used to check the handbook constants against each other.
struct CjState {
  double pressure;         // Pa
  double velocity;         // m/s, detonation velocity
  double relative_volume;  // V_CJ / V0
};
CjState chapmanJouguet(const JwlParams& j);

// The CJ isentrope of JWL detonation products: the energy per unit initial volume E_s(V) of the
// products taken from the CJ state (E_CJ = E0 + p_CJ (1 - V_CJ) / 2) without dissipation,
// dE/dV = -p(V, E), integrated once (RK4) into a table uniform in ln V, from V = 0.3 (products
// compressed beyond CJ, as at a reflection) to V = 1e5. The products of an ideal detonation lie on
// it; every other isentrope of a JWL set is E = E_s(V) + c V^-omega (constant Grueneisen omega),
// which is how the solver tracks the products' entropy (SolverOptions::products_adiabat).
class JwlIsentrope {
 public:
  explicit JwlIsentrope(const JwlParams& j);
  double energy(double relative_volume) const;   // Pa (J per m3 of unreacted explosive)
  static bool covers(double relative_volume) { return relative_volume >= 0.3 && relative_volume <= 1e5; }

 private:
  static constexpr double kLnVMin = -1.2039728043259361;   // ln 0.3
  static constexpr double kLnVMax = 11.512925464970229;    // ln 1e5 (vented products reach air's density)
  double inv_step_ = 0.0;
  std::vector<double> e_;   // at ln V = kLnVMin + i / inv_step_
};

}  // namespace ejecta::materials
