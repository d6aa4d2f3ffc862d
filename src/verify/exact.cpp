#include "verify/exact.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace ejecta::verify {

ExactRiemann::ExactRiemann(GasState left, GasState right, double gamma) : l_(left), r_(right), g_(gamma) {
  // Newton iteration on f_L(p) + f_R(p) + du = 0 from the two-rarefaction guess.
  const double cl = std::sqrt(g_ * l_.p / l_.rho), cr = std::sqrt(g_ * r_.p / r_.rho);
  const double z = (g_ - 1.0) / (2.0 * g_);
  double p = std::pow((cl + cr - 0.5 * (g_ - 1.0) * (r_.u - l_.u)) / (cl / std::pow(l_.p, z) + cr / std::pow(r_.p, z)), 1.0 / z);
  for (int it = 0; it < 100; ++it) {
    double dl, dr;
    const double fv = f(p, l_, dl) + f(p, r_, dr) + r_.u - l_.u;
    const double pn = std::max(1e-12, p - fv / (dl + dr));
    if (std::abs(pn - p) < 1e-14 * (pn + p)) {
      p = pn;
      break;
    }
    p = pn;
  }
  p_star_ = p;
  double d1, d2;
  u_star_ = 0.5 * (l_.u + r_.u) + 0.5 * (f(p, r_, d2) - f(p, l_, d1));
}

double ExactRiemann::f(double p, const GasState& s, double& dfdp) const {
  const double c = std::sqrt(g_ * s.p / s.rho);
  if (p > s.p) {
    const double a = 2.0 / ((g_ + 1.0) * s.rho), b = (g_ - 1.0) / (g_ + 1.0) * s.p;
    const double q = std::sqrt(a / (p + b));
    dfdp = q * (1.0 - 0.5 * (p - s.p) / (p + b));
    return (p - s.p) * q;
  }
  const double pr = p / s.p;
  dfdp = 1.0 / (s.rho * c) * std::pow(pr, -(g_ + 1.0) / (2.0 * g_));
  return 2.0 * c / (g_ - 1.0) * (std::pow(pr, (g_ - 1.0) / (2.0 * g_)) - 1.0);
}

GasState ExactRiemann::sample(double xi) const {
  const double g = g_;
  const bool left_side = xi <= u_star_;
  const GasState& s = left_side ? l_ : r_;
  const double sgn = left_side ? 1.0 : -1.0;   // mirror the right side onto the left formulas
  const double c = std::sqrt(g * s.p / s.rho);
  const double x = sgn * xi, u = sgn * s.u, us = sgn * u_star_;
  GasState out;
  if (p_star_ > s.p) {   // shock
    const double pr = p_star_ / s.p;
    const double speed = u - c * std::sqrt((g + 1.0) / (2.0 * g) * pr + (g - 1.0) / (2.0 * g));
    if (x <= speed) out = {s.rho, u, s.p};
    else out = {s.rho * (pr + (g - 1.0) / (g + 1.0)) / ((g - 1.0) / (g + 1.0) * pr + 1.0), us, p_star_};
  } else {   // rarefaction
    const double cs = c * std::pow(p_star_ / s.p, (g - 1.0) / (2.0 * g));
    const double head = u - c, tail = us - cs;
    if (x <= head) out = {s.rho, u, s.p};
    else if (x >= tail) out = {s.rho * std::pow(p_star_ / s.p, 1.0 / g), us, p_star_};
    else {
      const double k = 2.0 / (g + 1.0) + (g - 1.0) / ((g + 1.0) * c) * (u - x);
      out = {s.rho * std::pow(k, 2.0 / (g - 1.0)), 2.0 / (g + 1.0) * (c + 0.5 * (g - 1.0) * u + x), s.p * std::pow(k, 2.0 * g / (g - 1.0))};
    }
  }
  out.u *= sgn;
  return out;
}

double sedovAlpha(int nu) {
  if (nu == 2) return 0.984041;
  if (nu == 3) return 0.851060;
  throw InputError("sedov", "only cylindrical (2) and spherical (3) blasts are tabulated");
}

double sedovRadius(int nu, double energy, double rho, double t) {
  return std::pow(energy * t * t / (sedovAlpha(nu) * rho), 1.0 / (nu + 2.0));
}

double nohDensity(double r, double t) { return r < t / 3.0 ? 16.0 : 1.0 + t / std::max(r, 1e-300); }

double kinneyGrahamOverpressure(double z, double p_ambient) {
  const double a = z / 4.5, b = z / 0.048, c = z / 0.32, d = z / 1.35;
  return p_ambient * 808.0 * (1.0 + a * a) / std::sqrt((1.0 + b * b) * (1.0 + c * c) * (1.0 + d * d));
}

SandShock sandPistonShock(const materials::Material& sand, double up) {
  const auto& model = *sand.sand_model;
  const double rho0 = sand.referenceDensity();
  // The energy jump from rest at zero stress gives the shocked sand e = up^2 / 2 whatever the strain;
  // its energy term p_th = gamma T(x) rho0 e adds to the compaction curve's pressure (and so to the
  // friction strength), as the hydrocode's sand evaluates it.
  const double e1 = 0.5 * up * up;
  auto axial = [&](double eps) {
    const double x = -std::log(1.0 - eps);
    const double p = model.pressureAtNaturalStrain(x) + model.thermalGamma() * model.thermalFactor(x) * rho0 * e1;
    return p + 2.0 / 3.0 * std::min(sand.sand_slope * p, sand.sand_plateau);
  };
  // sigma(eps) * eps = rho0 up^2 (mass and momentum jumps with eps = up / Us)
  double lo = 1e-9, hi = 0.95;
  const double target = rho0 * up * up;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (axial(mid) * mid < target ? lo : hi) = mid;
  }
  const double eps = 0.5 * (lo + hi);
  return {up / eps, eps, axial(eps)};
}

ElasticPrecursor elasticPrecursor(const materials::Material& solid) {
  const double k = solid.mg.rho0 * solid.mg.c0 * solid.mg.c0, g = solid.strength.shear_modulus;
  const double m = k + 4.0 / 3.0 * g;
  return {m * solid.strength.yield / (2.0 * g), std::sqrt(m / solid.mg.rho0)};
}

TaylorWave::TaylorWave(const materials::JwlParams& j) : cj_(materials::chapmanJouguet(j)) {
  // Isentrope through CJ: p_s(V) = A e^(-R1 V) + B e^(-R2 V) + C V^-(1+w).
  const double vcj = cj_.relative_volume;
  const double c_coef = (cj_.pressure - j.a * std::exp(-j.r1 * vcj) - j.b * std::exp(-j.r2 * vcj)) * std::pow(vcj, 1.0 + j.omega);
  auto ps = [&](double v) { return j.a * std::exp(-j.r1 * v) + j.b * std::exp(-j.r2 * v) + c_coef * std::pow(v, -(1.0 + j.omega)); };
  auto sound = [&](double v) {
    const double dpdv = -j.r1 * j.a * std::exp(-j.r1 * v) - j.r2 * j.b * std::exp(-j.r2 * v) - (1.0 + j.omega) * c_coef * std::pow(v, -(2.0 + j.omega));
    return std::sqrt(std::max(-v * v / j.rho0 * dpdv, 0.0));
  };
  double v = vcj, u = cj_.velocity * (1.0 - vcj);
  const double dv = 1e-5;
  std::vector<double> xi, p;
  xi.push_back(u + sound(v));
  p.push_back(ps(v));
  while (u > 0.0 && v < 50.0) {   // u(V) = u_CJ - int c / V dV along the C- invariant
    const double c0 = sound(v), c1 = sound(v + dv);
    u -= 0.5 * (c0 / v + c1 / (v + dv)) * dv;
    v += dv;
    xi.push_back(u + c1);
    p.push_back(ps(v));
  }
  std::reverse(xi.begin(), xi.end());
  std::reverse(p.begin(), p.end());
  xi_ = std::move(xi);
  p_ = std::move(p);
  xi_wall_ = xi_.front();
  p_wall_ = p_.front();
}

double TaylorWave::pressure(double x) const {
  if (x <= xi_wall_) return p_wall_;
  if (x > xi_.back()) return 0.0;
  const auto it = std::upper_bound(xi_.begin(), xi_.end(), x);
  const std::size_t i = static_cast<std::size_t>(it - xi_.begin());
  const double t = (x - xi_[i - 1]) / (xi_[i] - xi_[i - 1]);
  return p_[i - 1] + t * (p_[i] - p_[i - 1]);
}

}  // namespace ejecta::verify
