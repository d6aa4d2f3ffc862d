#include "materials/constituents.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/interp.hpp"

namespace ejecta::materials {

double QuartzParams::strain(double p) const {
  return 1.0 - std::pow(1.0 + dK_dp * p / bulk_modulus, -1.0 / dK_dp);
}

double QuartzParams::compliance(double p) const {
  return std::pow(1.0 + dK_dp * p / bulk_modulus, -1.0 / dK_dp - 1.0) / bulk_modulus;
}

namespace {
double denominator(const WaterEosSet& w, double mu) {
  return 1.0 - (w.s1 - 1.0) * mu - w.s2 * mu * mu / (1.0 + mu) - w.s3 * mu * mu * mu / ((1.0 + mu) * (1.0 + mu));
}
}  // namespace

double WaterEosSet::hugoniotPressure(double eta) const {
  const double mu = eta / (1.0 - eta);
  const double d = denominator(*this, mu);
  return rho0 * c0 * c0 * mu * (1.0 + mu) / (d * d);
}

double WaterEosSet::hugoniotStiffness(double eta) const {
  const double mu = eta / (1.0 - eta);
  const double d = denominator(*this, mu);
  const double dd = -(s1 - 1.0) - s2 * (mu * mu + 2.0 * mu) / ((1.0 + mu) * (1.0 + mu)) -
                    s3 * (3.0 * mu * mu + mu * mu * mu) / ((1.0 + mu) * (1.0 + mu) * (1.0 + mu));
  const double f = mu * (1.0 + mu), df = 1.0 + 2.0 * mu;
  const double dp_dmu = rho0 * c0 * c0 * (df * d - 2.0 * f * dd) / (d * d * d);
  return dp_dmu / ((1.0 - eta) * (1.0 - eta));
}

double WaterEosSet::etaAsymptote() const {
  // The denominator falls from 1 at mu = 0; its first zero bounds the Hugoniot.
  double hi = 1.0;
  while (denominator(*this, hi) > 0.0 && hi < 1e6) hi *= 2.0;
  const double mu = bisect([&](double m) { return -denominator(*this, m); }, 0.0, hi);
  return mu / (1.0 + mu);
}

double WaterEosSet::strainAtPressure(double p) const {
  if (p <= 0.0) return p / bulkModulus();
  const double top = etaAsymptote() * (1.0 - 1e-12);
  return bisect([&](double e) { return hugoniotPressure(e) - p; }, 0.0, top);
}

WaterEosSet waterAwg() { return {"awg", 1000.0, 1500.0, 1.75, 0.0, 0.0, 0.28, "verified"}; }
WaterEosSet waterAlt() { return {"alt", 1000.0, 1647.0, 1.921, -0.096, 0.0, 0.35, "recalled"}; }

WaterEosSet waterEosByName(const std::string& name) {
  if (name == "awg") return waterAwg();
  if (name == "alt") return waterAlt();
  throw InputError("water-eos", "unknown set '" + name + "' (valid: awg, alt)");
}

}  // namespace ejecta::materials
