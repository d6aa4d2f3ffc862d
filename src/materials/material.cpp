#include "materials/material.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace ejecta::materials {

namespace {
void requirePositive(const std::string& mat, const char* field, double v, const char* unit) {
  if (!(v > 0.0) || !std::isfinite(v))
    throw InputError(fmt::format("material.{}.{}", mat, field), fmt::format("{:g} {} is out of range; valid > 0 {}", v, unit, unit));
}
}  // namespace

double Material::referenceDensity() const {
  switch (eos) {
    case EosKind::IdealGas: return 1.225;
    case EosKind::Jwl: return jwl.rho0;
    case EosKind::MieGruneisen: return mg.rho0;
    case EosKind::Sand: return sand->referenceDensity();
  }
  return 1.0;
}

void Material::validate() const {
  switch (eos) {
    case EosKind::IdealGas:
      if (!(gas.gamma > 1.0 && gas.gamma < 5.0))
        throw InputError(fmt::format("material.{}.gamma", name), fmt::format("{:g} is out of range; valid (1, 5)", gas.gamma));
      break;
    case EosKind::Jwl:
      requirePositive(name, "rho0", jwl.rho0, "kg/m3");
      requirePositive(name, "A", jwl.a, "Pa");
      requirePositive(name, "B", jwl.b, "Pa");
      requirePositive(name, "R1", jwl.r1, "-");
      requirePositive(name, "R2", jwl.r2, "-");
      requirePositive(name, "omega", jwl.omega, "-");
      requirePositive(name, "E0", jwl.e0, "Pa");
      requirePositive(name, "D", jwl.d_cj, "m/s");
      if (!(jwl.burn_width >= 0.5 && jwl.burn_width <= 10.0))
        throw InputError(fmt::format("material.{}.burn_width", name), fmt::format("{:g} cells is out of range; valid [0.5, 10]", jwl.burn_width));
      break;
    case EosKind::MieGruneisen:
      requirePositive(name, "rho0", mg.rho0, "kg/m3");
      requirePositive(name, "C", mg.c0, "m/s");
      if (!(mg.s1 >= 1.0 && mg.s1 < 4.0))
        throw InputError(fmt::format("material.{}.S1", name), fmt::format("{:g} is out of range; valid [1, 4)", mg.s1));
      if (!(mg.gamma0 >= 0.0 && mg.gamma0 < 4.0))
        throw InputError(fmt::format("material.{}.gamma0", name), fmt::format("{:g} is out of range; valid [0, 4)", mg.gamma0));
      break;
    case EosKind::Sand:
      if (!sand || !sand_model) throw InputError(fmt::format("material.{}", name), "sand material without a sand model");
      break;
  }
  if (strength.kind == StrengthKind::VonMises) {
    requirePositive(name, "shear_modulus", strength.shear_modulus, "Pa");
    requirePositive(name, "yield", strength.yield, "Pa");
  }
}

Material idealGas(std::string name, double gamma) {
  Material m;
  m.name = std::move(name);
  m.eos = EosKind::IdealGas;
  m.gas.gamma = gamma;
  m.validate();
  return m;
}

Material air() { return idealGas("air", 1.4); }

Material explosive(const std::string& name) {
  // shared/data/explosives_jwl.csv (LLNL Explosives Handbook, Dobratz & Crawford 1985).
  struct Row { const char* name; double rho0, a, b, r1, r2, w, e0, d, pcj; };
  static constexpr Row rows[] = {
      {"C4", 1601, 609.77e9, 12.95e9, 4.5, 1.4, 0.25, 9.0e9, 8193, 28.0e9},
      {"CompB", 1717, 524.2e9, 7.678e9, 4.20, 1.10, 0.34, 8.5e9, 7980, 29.5e9},
      {"TNT", 1630, 371.2e9, 3.231e9, 4.15, 0.95, 0.30, 7.0e9, 6930, 21.0e9},
  };
  for (const auto& r : rows) {
    if (name != r.name) continue;
    Material m;
    m.name = name;
    m.eos = EosKind::Jwl;
    m.jwl = {r.rho0, r.a, r.b, r.r1, r.r2, r.w, r.e0, r.d, r.pcj, 2.0};
    return m;
  }
  throw InputError("explosive", fmt::format("'{}' is unknown; valid C4, CompB, TNT", name));
}

Material water() {
  Material m;
  m.name = "water";
  m.eos = EosKind::MieGruneisen;
  m.mg = {1000.0, 1500.0, 1.75, 0.28, -1.0e5};   // LS-DYNA AWG set (shared/data, verified)
  return m;
}

Material steel() {
  // Ours, typical of rolled steel (Steinberg's 4340 Hugoniot, a mild-steel flow stress): rho0 7850,
  // C 4570 m/s, S1 1.49, gamma0 1.93, G 80 GPa, Y 350 MPa. Only the verification problem uses it.
  Material m;
  m.name = "steel";
  m.eos = EosKind::MieGruneisen;
  m.mg = {7850.0, 4570.0, 1.49, 1.93, -2.0e9};
  m.strength = {StrengthKind::VonMises, 80.0e9, 350.0e6};
  return m;
}

Material sand(const SandInputs& inputs, const std::string& name) {
  Material m;
  m.name = name;
  m.eos = EosKind::Sand;
  m.sand_model = std::make_shared<const SandModel>(inputs);
  m.sand = std::make_shared<const SandPointEos>(*m.sand_model);
  m.sand_slope = inputs.friction_slope;
  m.sand_plateau = m.sand_model->yieldPlateau();
  m.strength.kind = StrengthKind::PseudoTensor;
  return m;
}

CjState chapmanJouguet(const JwlParams& j) {
  // Products' Hugoniot centred on (V = 1, p = 0, E = E0):  E = E0 + p (1 - V) / 2 (per initial
  // volume), so p (1 - w (1 - V) / (2V)) = f(V) + w E0 / V. D^2 = p / (rho0 (1 - V)) is least at CJ.
  auto hugoniot = [&](double v) {
    const double f = j.a * (1.0 - j.omega / (j.r1 * v)) * std::exp(-j.r1 * v) +
                     j.b * (1.0 - j.omega / (j.r2 * v)) * std::exp(-j.r2 * v);
    return (f + j.omega * j.e0 / v) / (1.0 - j.omega * (1.0 - v) / (2.0 * v));
  };
  auto d2 = [&](double v) { return hugoniot(v) / (j.rho0 * (1.0 - v)); };
  double lo = 0.4, hi = 0.99;   // golden-section search on the convex D^2(V)
  const double gr = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = hi - gr * (hi - lo), b = lo + gr * (hi - lo);
  for (int it = 0; it < 200; ++it) {
    if (d2(a) < d2(b)) hi = b; else lo = a;
    a = hi - gr * (hi - lo);
    b = lo + gr * (hi - lo);
  }
  const double v = 0.5 * (lo + hi);
  return {hugoniot(v), std::sqrt(d2(v)), v};
}

JwlIsentrope::JwlIsentrope(const JwlParams& j) {
  const auto cj = chapmanJouguet(j);
  auto p = [&j](double V, double E) {
    return j.a * (1.0 - j.omega / (j.r1 * V)) * std::exp(-j.r1 * V) + j.b * (1.0 - j.omega / (j.r2 * V)) * std::exp(-j.r2 * V) + j.omega * E / V;
  };
  // dE/dlnV = -p V, stepped in ln V from CJ both ways, 16 sub-steps per table interval.
  constexpr int kPoints = 4001, kSub = 16;
  const double step = (kLnVMax - kLnVMin) / (kPoints - 1);
  inv_step_ = 1.0 / step;
  e_.assign(kPoints, 0.0);
  const double x_cj = std::log(cj.relative_volume), e_cj = j.e0 + 0.5 * cj.pressure * (1.0 - cj.relative_volume);
  auto integrate = [&](double x0, double e0, double x1) {
    const int n = std::max(1, static_cast<int>(std::ceil(std::abs(x1 - x0) * inv_step_ * kSub)));
    const double h = (x1 - x0) / n;
    auto f = [&](double x, double E) { const double V = std::exp(x); return -p(V, E) * V; };
    double x = x0, E = e0;
    for (int i = 0; i < n; ++i) {
      const double k1 = f(x, E), k2 = f(x + 0.5 * h, E + 0.5 * h * k1), k3 = f(x + 0.5 * h, E + 0.5 * h * k2), k4 = f(x + h, E + h * k3);
      E += h * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0;
      x += h;
    }
    return E;
  };
  const int i_cj = static_cast<int>(std::floor((x_cj - kLnVMin) * inv_step_));
  double x = x_cj, E = e_cj;
  for (int i = i_cj + 1; i < kPoints; ++i) {   // expansion
    const double xi = kLnVMin + i * step;
    E = integrate(x, E, xi);
    x = xi;
    e_[static_cast<std::size_t>(i)] = E;
  }
  x = x_cj;
  E = e_cj;
  for (int i = i_cj; i >= 0; --i) {   // compression
    const double xi = kLnVMin + i * step;
    E = integrate(x, E, xi);
    x = xi;
    e_[static_cast<std::size_t>(i)] = E;
  }
}

double JwlIsentrope::energy(double relative_volume) const {
  const double u = std::clamp((std::log(relative_volume) - kLnVMin) * inv_step_, 0.0, static_cast<double>(e_.size() - 1));
  const std::size_t i = std::min(static_cast<std::size_t>(u), e_.size() - 2);
  const double w = u - static_cast<double>(i);
  return e_[i] + w * (e_[i + 1] - e_[i]);
}


namespace {
// An ideal gas's batch (evaluateEosAndHistory): a plain loop over restrict-qualified arrays. (GCC 12
// leaves it scalar: it sinks the density's load into a branch; docs/solver.md, Speed.) Its history
// is its h0, left as it is.
[[gnu::noinline]] void idealGasBatch(double gamma, std::ptrdiff_t n, const double* __restrict alpha, const double* __restrict rho,
                                     const double* __restrict e, double* __restrict pressure, double* __restrict bulk) {
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const double ei = e[i] > 0.0 ? e[i] : 0.0;
    const double p = (gamma - 1.0) * rho[i] * ei, k = gamma * p + 1e-6;
    const bool present = alpha[i] > 0.0;
    pressure[i] = present ? p : 0.0;
    bulk[i] = present ? k : 0.0;
  }
}
}  // namespace

void evaluateEosAndHistory(const Material& m, std::ptrdiff_t n, const double* alpha, const double* rho, const double* e, double* history,
                           double* pressure, double* bulk) noexcept {
  if (m.eos == EosKind::IdealGas) {
    idealGasBatch(m.gas.gamma, n, alpha, rho, e, pressure, bulk);
    for (std::ptrdiff_t i = 0; i < n; ++i)
      if (!(alpha[i] > 0.0)) history[i] = 0.0;
    return;
  }
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (!(alpha[i] > 0.0)) {
      pressure[i] = bulk[i] = history[i] = 0.0;
      continue;
    }
    const double h0 = history[i];
    const auto st = evaluateEosAndHistory(m, rho[i], e[i], h0, history[i]);
    pressure[i] = st.pressure;
    bulk[i] = st.bulk;
  }
}
}  // namespace ejecta::materials
