#include "materials/sand_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/error.hpp"

namespace ejecta::materials {

namespace {
constexpr double kWaterDensity = 1000.0;   // kg/m3, for the volume of the pore water (verified)
constexpr double kWaterHeatCapacity = 4180.0;   // J/(kg K), for the energy term's weights (recalled handbook value)

// The model's own inputs, checked as the deck's are (core/range.hpp: one message, one rule).
void requireRange(const char* field, double v, double lo, double hi, const char* unit, bool lo_open, bool hi_open) {
  requireInRange(field, v, Range{lo, hi, lo_open, hi_open}, unit);
}
}  // namespace

SandInputs SandInputs::fromWetDensity(double wet_density, double moisture) {
  requireRange("wet-density", wet_density, 0.0, 1e5, "kg/m3", true, true);
  requireInRange("moisture", moisture, kMoistureRange, "-");
  SandInputs in;
  in.dry_density = wet_density / (1.0 + moisture);
  in.moisture = moisture;
  return in;
}

// ---------------------------------------------------------------------------------------------
VoidSpring::VoidSpring(const QuartzParams& quartz) {
  n_ref_ = 1.0 - kSjoboDensity / quartz.grain_density;
  std::vector<double> p, e;
  for (const auto& row : kSjoboTable) {
    const double eps = 1.0 - kSjoboDensity / row.density;
    p.push_back(row.pressure);
    e.push_back((eps - (1.0 - n_ref_) * quartz.strain(row.pressure)) / n_ref_);
  }
  p_table_end_ = p.back();
  // The baseline's densest row (2671 kg/m3 at 651 MPa) must still have open voids: grains lighter
  // than that (with their compression) leave none, and the skeleton's curve would run backwards.
  for (std::size_t i = 1; i < e.size(); ++i)
    if (!(e[i] > e[i - 1]) || !(e[i] < 1.0))
      throw InputError("grain-density", fmt::format("{:g} kg/m3 is too light for the dry Sjobo baseline, which reaches {:g} kg/m3 at {:.0f} MPa; "
                                                    "valid: grains that still leave it voids (about 2640 kg/m3 or more with these quartz moduli) up to 5000 kg/m3",
                                                    quartz.grain_density, kSjoboTable.back().density, kSjoboTable.back().pressure / 1e6));
  // Beyond the last measured point the voids close along the last measured slope: this fixes
  // a definite lockup pressure where the skeleton becomes rigid (closure = 1).
  const std::size_t m = p.size();
  const double slope = (e[m - 1] - e[m - 2]) / (p[m - 1] - p[m - 2]);
  p_lock_ = p[m - 1] + (1.0 - e[m - 1]) / slope;
  p.push_back(p_lock_);
  e.push_back(1.0);
  curve_ = MonotoneCubic(p, e);

  // Unloading: the measured dry unloading modulus K = rho c^2 less the quartz compliance. Where
  // the provisional data would make the skeleton stiffer than rigid, or softer than on loading,
  // it is clamped: unloading is never softer than loading and never negative.
  for (std::size_t i = 0; i < kSjoboTable.size(); ++i) {
    const auto& row = kSjoboTable[i];
    const double eps = 1.0 - kSjoboDensity / row.density;
    const double column_compliance = (1.0 - eps) / (row.density * row.sound_speed * row.sound_speed);
    double c = (column_compliance - (1.0 - n_ref_) * quartz.compliance(row.pressure)) / n_ref_;
    c = std::clamp(c, 0.0, compliance(row.pressure));
    unload_e_.push_back(closure(row.pressure));
    unload_c_.push_back(c);
  }
  unload_e_.push_back(1.0);
  unload_c_.push_back(0.0);
}

double VoidSpring::closure(double p) const { return p <= 0.0 ? 0.0 : (p >= p_lock_ ? 1.0 : curve_(p)); }

double VoidSpring::compliance(double p) const {
  return p >= p_lock_ ? 0.0 : std::max(0.0, curve_.derivative(std::max(p, 0.0)));
}

double VoidSpring::unloadingCompliance(double p) const {
  const double e = closure(p);
  auto it = std::upper_bound(unload_e_.begin(), unload_e_.end(), e);
  std::size_t i = std::clamp<std::ptrdiff_t>(it - unload_e_.begin() - 1, 0, unload_e_.size() - 2);
  const double t = std::clamp((e - unload_e_[i]) / (unload_e_[i + 1] - unload_e_[i]), 0.0, 1.0);
  const double c = unload_c_[i] + t * (unload_c_[i + 1] - unload_c_[i]);
  return std::min(c, compliance(p));
}

double VoidSpring::pressureAtClosure(double e) const {
  if (e <= 0.0) return 0.0;
  if (e >= 1.0) return p_lock_;
  return bisect([&](double p) { return closure(p) - e; }, 0.0, p_lock_);
}

// ---------------------------------------------------------------------------------------------
SandModel::SandModel(const SandInputs& in) : in_(in), void_((
    [&] {
      requireRange("grain-density", in.quartz.grain_density, 1000.0, 5000.0, "kg/m3", false, false);
      requireRange("quartz-bulk-modulus", in.quartz.bulk_modulus, 1e9, 1e12, "Pa", false, false);
      requireRange("quartz-dK-dp", in.quartz.dK_dp, 1.0, 12.0, "-", false, false);
      return in.quartz;
    }())) {
  // porosity at most max_porosity (SandInputs): below that the baseline curve is stretched past meaning
  requireRange("dry-density", in.dry_density, (1.0 - std::min(in.max_porosity, 1.0)) * in.quartz.grain_density, in.quartz.grain_density, "kg/m3",
               in.max_porosity >= 1.0, true);
  requireInRange("moisture", in.moisture, kMoistureRange, "-");
  requireRange("friction-slope", in.friction_slope, 0.0, 10.0, "-", false, false);
  requireRange("tension-cutoff", in.tension_cutoff, -1e9, 0.0, "Pa", false, false);
  requireRange("poisson", in.poisson, -1.0, 0.5, "-", true, true);
  requireInRange("plateau-scale", in.plateau.scale, kPlateauScaleRange, "-");
  requireRange("pore-pressure", in.pore_pressure, 0.0, 1e7, "Pa", false, false);
  requireRange("plateau-residual", in.plateau.residual, 0.0, 1e10, "Pa", false, false);
  requireRange("yield-plateau", in.plateau.fixed, 0.0, 1e10, "Pa", false, false);
  if (in.thermal_gamma != -1.0) requireInRange("thermal-gamma", in.thermal_gamma, kThermalGammaRange, "- (or -1: from the constituents)");
  requireInRange("min-poisson-ratio", in.min_poisson_ratio, kMinPoissonRatioRange, "-");
  if (in.shear_modulus_cap != 0.0) requireInRange("shear-modulus-cap", in.shear_modulus_cap, kShearModulusCapRange, "Pa (or 0: quartz's)");

  SandState s{};
  s.dry_density = in.dry_density;
  s.moisture = in.moisture;
  s.wet_density = in.dry_density * (1.0 + in.moisture);
  s.porosity = 1.0 - in.dry_density / in.quartz.grain_density;
  s.water_fraction = in.moisture * in.dry_density / kWaterDensity;
  s.saturation = s.water_fraction / s.porosity;
  if (s.saturation > 1.0 + 1e-9) {
    const double w_max = s.porosity * kWaterDensity / in.dry_density;
    throw InputError("moisture", fmt::format("{:.4g}% gives saturation {:.1f}% at dry density {:g} kg/m3; "
                                             "valid [0, {:.4g}%] (saturation at most 100%)",
                                             100.0 * in.moisture, 100.0 * s.saturation, in.dry_density,
                                             100.0 * w_max));
  }
  s.saturation = std::min(s.saturation, 1.0);
  s.water_fraction = std::min(s.water_fraction, s.porosity);
  s.air_voids = s.porosity - s.water_fraction;
  state_ = s;
  water_eta_top_ = in.water.etaAsymptote() * (1.0 - 1e-12);

  if (in.plateau.law == PlateauParams::Law::Fixed) {
    plateau_ = in.plateau.fixed;
  } else {
    const double p_skeleton = void_.pressureAtClosure(s.air_voids / s.porosity);
    plateau_ = std::max(in.plateau.scale * in.friction_slope * p_skeleton, in.plateau.residual);
  }
  // The energy term's Gruneisen coefficient from the constituents (see thermalGamma()).
  {
    const double phi_q = 1.0 - s.porosity, phi_w = s.water_fraction;
    const auto& q = in.quartz;
    const double cw = kWaterHeatCapacity, Kw = in.water.bulkModulus();
    const double rc_q = q.grain_density * q.heat_capacity, rc_w = kWaterDensity * cw;
    const double comp = phi_q / q.bulk_modulus + phi_w / Kw;
    const double p_per_dT = (phi_q / q.bulk_modulus * q.gruneisen * rc_q + phi_w / Kw * in.water.gamma0 * rc_w) / comp;
    // per unit volume of the compacted state (air voids closed), where the term applies fully
    const double e_per_dT = (phi_q * rc_q + phi_w * rc_w) / (phi_q + phi_w);
    thermal_gamma_ = in.thermal_gamma >= 0.0 ? in.thermal_gamma : p_per_dT / e_per_dT;
  }
  // The Sjobo reference skeleton at zero strain anchors the shear modulus (G0 = 76.9 MPa).
  const double n_ref = void_.referencePorosity();
  skeleton_ref_compliance_ = n_ref * void_.unloadingCompliance(0.0) + (1.0 - n_ref) * in.quartz.compliance(0.0);
  lockup_strain_ = std::max(naturalStrain(void_.lockupPressure()), 1e-6);
}

double SandModel::waterStrain(double p) const {
  if (p <= 0.0) return p / in_.water.bulkModulus();
  return bisect([&](double e) { return in_.water.hugoniotPressure(e) - p; }, 0.0, water_eta_top_);
}

double SandModel::strain(double p) const {
  // Three springs in series: one pressure, the strains add, each weighted by its gauge length.
  return state_.air_voids * void_.closure(p) + (1.0 - state_.porosity) * in_.quartz.strain(p) +
         state_.water_fraction * waterStrain(p);
}

double SandModel::naturalStrain(double p) const { return -std::log1p(-strain(p)); }

double SandModel::compliance(double p, bool unloading) const {
  const double c_void = unloading ? void_.unloadingCompliance(p) : void_.compliance(p);
  double c = state_.air_voids * c_void + (1.0 - state_.porosity) * in_.quartz.compliance(p);
  if (state_.water_fraction > 0.0)
    c += state_.water_fraction / in_.water.hugoniotStiffness(std::max(waterStrain(p), 0.0));
  return c;
}

double SandModel::loadingModulus(double p) const { return (1.0 - strain(p)) / compliance(p, false); }
double SandModel::unloadingModulus(double p) const { return (1.0 - strain(p)) / compliance(p, true); }

double SandModel::shearModulus(double p) const {
  // Shear is carried by the grain skeleton alone (pore water has none): G scales with the
  // skeleton's unloading stiffness, anchored to the measured Sjobo G0, capped at quartz's (or at
  // the input cap below it), and at most what the bounding Poisson's ratio gives on the whole
  // mixture's unloading bulk modulus (the skeleton's compliance alone misses the (1 - strain)
  // factor and the pore water's series compliance that K_u carries).
  const double n = state_.porosity;
  const double c_skel = n * void_.unloadingCompliance(p) + (1.0 - n) * in_.quartz.compliance(p);
  const double nu = in_.min_poisson_ratio;
  const double g_poisson = 1.5 * (1.0 - 2.0 * nu) / (1.0 + nu) * unloadingModulus(p);
  return std::min({kSjoboShearModulus * skeleton_ref_compliance_ / c_skel, g_poisson, shearModulusCap()});
}

double SandModel::yieldStrength(double p) const {
  return std::min(in_.friction_slope * std::max(p, 0.0), plateau_);
}

double SandModel::pressureAtNaturalStrain(double x) const {
  if (x <= 0.0) return loadingModulus(0.0) * x;
  double hi = 1e6;
  while (naturalStrain(hi) < x) {
    hi *= 4.0;
    if (hi > 1e15) throw InputError("strain", fmt::format("natural strain {:g} is beyond the soil's range", x));
  }
  return bisect([&](double p) { return naturalStrain(p) - x; }, 0.0, hi);
}

CurvePoint SandModel::pointAt(double p) const {
  CurvePoint c{};
  c.pressure = p;
  c.strain = strain(p);
  c.natural_strain = -std::log1p(-c.strain);
  c.density = state_.wet_density / (1.0 - c.strain);
  c.loading_modulus = loadingModulus(p);
  c.unloading_modulus = unloadingModulus(p);
  c.shear_modulus = shearModulus(p);
  return c;
}

std::vector<CurvePoint> SandModel::sampleLoading(int n) const {
  std::vector<CurvePoint> out;
  out.reserve(static_cast<std::size_t>(n) + 1);
  out.push_back(pointAt(0.0));
  const double p_lo = 1e3;   // Pa: the curve below 1 kPa is linear
  for (int i = 0; i < n; ++i) out.push_back(pointAt(p_lo * std::pow(p_max_ / p_lo, double(i) / (n - 1))));
  return out;
}

double SandModel::thermalFactor(double x) const {
  const double f = x <= 0.0 ? 0.0 : (x >= lockup_strain_ ? 1.0 : x / lockup_strain_);
  return f * std::exp(std::max(x, 0.0));
}

SandKeyNumbers SandModel::keyNumbers() const {
  SandKeyNumbers k{};
  const double rho = state_.wet_density;
  k.initial_bulk_modulus = loadingModulus(0.0);
  k.initial_unloading_modulus = unloadingModulus(0.0);
  k.initial_shear_modulus = shearModulus(0.0);
  k.lockup_pressure = void_.lockupPressure();
  k.lockup_strain = naturalStrain(k.lockup_pressure);
  k.lockup_density = rho * std::exp(k.lockup_strain);
  k.yield_plateau = plateau_;
  k.friction_knee_pressure = in_.friction_slope > 0.0 ? plateau_ / in_.friction_slope : 0.0;
  k.loading_wave_speed = std::sqrt(k.initial_bulk_modulus / rho);
  k.elastic_wave_speed = std::sqrt((k.initial_unloading_modulus + 4.0 / 3.0 * k.initial_shear_modulus) / rho);
  const double n = state_.porosity;
  k.wood_bulk_modulus = 1.0 / ((1.0 - n) / in_.quartz.bulk_modulus + n / in_.water.bulkModulus());
  return k;
}

// ---------------------------------------------------------------------------------------------
SandPointEos::SandPointEos(const SandModel& model, int table_size) {
  if (table_size < 16) throw InputError("table-size", "must be at least 16");
  rho0_ = model.state().wet_density;
  p_cut_ = model.inputs().tension_cutoff;
  pore_p_ = model.inputs().pore_pressure;
  gamma_ = model.thermalGamma();
  x_lock_ = std::max(model.keyNumbers().lockup_strain, 1e-6);   // as SandModel::thermalFactor
  // Invert the loading curve once: sample it densely in pressure, then read the pressure at
  // each node of a uniform natural-strain grid by interpolation between samples.
  const int m = 40000;
  const double p_top = model.maxPressure(), p_lo = 1.0;
  std::vector<double> ps(m + 1), xs(m + 1);
  ps[0] = 0.0;
  xs[0] = 0.0;
  for (int j = 1; j <= m; ++j) {
    ps[j] = p_lo * std::pow(p_top / p_lo, double(j - 1) / (m - 1));
    xs[j] = model.naturalStrain(ps[j]);
  }
  const int n = table_size;
  dx_ = xs[m] / (n - 1);
  inv_dx_ = 1.0 / dx_;
  last_ = n - 2;
  p_.resize(n);
  k_load_.resize(n);
  k_unload_.resize(n);
  g_.resize(n);
  std::size_t j = 0;
  for (int i = 0; i < n; ++i) {
    const double x = i * dx_;
    while (j + 2 <= static_cast<std::size_t>(m) && xs[j + 1] < x) ++j;
    const double t = std::clamp((x - xs[j]) / (xs[j + 1] - xs[j]), 0.0, 1.0);
    const double p = ps[j] + t * (ps[j + 1] - ps[j]);
    p_[i] = p;
    k_load_[i] = model.loadingModulus(p);
    k_unload_[i] = model.unloadingModulus(p);
    g_[i] = model.shearModulus(p);
  }
  follow_pressure_ = model.inputs().shear_follows_pressure;
  gp_.resize(n);
  const double u_top = std::log1p(ps[m] * kInvShearPressureScale);
  inv_du_ = (n - 1) / u_top;
  for (int i = 0; i < n; ++i) gp_[i] = model.shearModulus(std::expm1(i / inv_du_) / kInvShearPressureScale);
}

}  // namespace ejecta::materials
