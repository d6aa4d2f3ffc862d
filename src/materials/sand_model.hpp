#pragma once
// The two-input sand model (shared/design/method.md section 2): dry density and gravimetric
// moisture give the whole constitutive description through three springs in series (air-void
// skeleton, quartz, water), the dry Sjobo sand as baseline, and a saturation-dependent
// strength plateau. SI units throughout: Pa, kg/m3, m/s.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/interp.hpp"
#include "core/range.hpp"
#include "materials/constituents.hpp"

namespace ejecta::materials {

// How the yield-strength plateau falls with saturation (the published values are not
// available to us). EffectiveStress, our default: grains carry shear only through the
// intergranular (effective) stress; under fast, undrained loading that stress stops rising once
// the pore air is squeezed out, because the pore water then takes every further increment. So
// the plateau is the friction strength at the skeleton pressure that closes the air voids:
//   Y_plateau = scale * (dY/dp) * p_skeleton(void closure = air voids / porosity),
// which is the dry lockup strength at S = 0 and falls to `residual` at S = 1.
struct PlateauParams {
  enum class Law { EffectiveStress, Fixed };
  Law law = Law::EffectiveStress;
  double scale = 1.0;      // - multiplier on the effective-stress plateau
  double residual = 0.0;   // Pa, floor (the undrained strength of saturated sand)
  double fixed = 0.0;      // Pa, the plateau when law == Fixed
};

// Valid ranges of the inputs that `ejecta soil` and the deck share (one declaration: the layers cannot
// disagree). Moisture has no upper bound of its own: the saturation it gives (at most 100%) bounds it.
inline constexpr Range kMoistureRange{0.0, INFINITY, false, true};   // - gravimetric
inline constexpr Range kPlateauScaleRange{0.0, 10.0};                // - on the effective-stress plateau
inline constexpr Range kThermalGammaRange{0.0, 4.0};                 // - the energy term's Gruneisen coefficient
inline constexpr Range kShearModulusCapRange{1e8, 45e9};             // Pa, the cap on the skeleton's shear modulus (at most quartz's)
inline constexpr Range kMinPoissonRatioRange{0.0, 0.45};             // -, the Poisson bound on the skeleton's shear modulus

struct SandInputs {
  double dry_density = 1280.0;   // kg/m3
  double moisture = 0.07;        // - gravimetric: mass of water / mass of dry solids
  QuartzParams quartz{};
  WaterEosSet water = waterAwg();
  double friction_slope = kSjoboFrictionSlope;   // - dY/dp of the initial (friction) branch
  double tension_cutoff = kSjoboTensionCutoff;   // Pa (negative)
  double poisson = kSjoboPoisson;                // - for the LS-DYNA card
  PlateauParams plateau{};
  // Gruneisen coefficient of the sand's energy term (p = C(x) + gamma T(x) rho0 e, LS-DYNA's
  // *EOS_TABULATED_COMPACTION form). Negative: derived from the constituents (SandModel::thermalGamma).
  double thermal_gamma = -1.0;   // -
  // The cap on the skeleton's shear modulus, Pa; 0: the quartz grains' own (a solid aggregate, the
  // bound). Compacted and crushed sand is not intact quartz: where it lies between is not measured,
  // so it is an input with a sensitivity (docs/sand-model.md).
  double shear_modulus_cap = 0.0;   // Pa
  // What the skeleton's shear modulus follows (docs/sand-model.md, Shear modulus): the largest
  // compaction the sand has seen (false: G stays where the loading took it, after unloading too, as
  // a solid aggregate would), or the present effective pressure (true: G as on the loading curve at
  // the pressure now, so unloaded sand, and a dust of it in the products, is as soft as sand at that
  // pressure, as a granular skeleton's modulus follows its confinement). Revision 11's default.
  bool shear_follows_pressure = true;
  // The skeleton's G is bounded by this Poisson's ratio on the unloading bulk modulus:
  // G <= 3 K_u (1 - 2 nu) / (2 (1 + nu)). Scaled from the dry skeleton's compliance alone, G would
  // exceed 1.5 K_u while the air voids close (nu < 0, which no granular material shows); the
  // default is the measured Poisson's ratio of the Sjobo sand that anchors G0 (docs/sand-model.md).
  double min_poisson_ratio = kSjoboPoisson;   // -
  // Porosity at most this: looser than any sand packing (random loose packing of spheres is about
  // 0.45, the loosest natural sands about 0.55). The model's bounding-case checks (a pure water
  // column, porosity -> 1) raise it to 1.
  double max_porosity = 0.7;     // -
  // The pore air's pressure, Pa. The compaction curve is the skeleton's effective stress; the
  // hydrocode's pressure is that plus the pore pressure, so sand as laid is in equilibrium with
  // the ambient air beside it (0: the curve alone, as the model's tests and cards use it).
  double pore_pressure = 0.0;    // Pa

  // Users often know the wet (gross) density: rho_d = rho_wet / (1 + w).
  static SandInputs fromWetDensity(double wet_density, double moisture);
};

struct SandState {
  double dry_density;      // kg/m3
  double moisture;         // -
  double wet_density;      // kg/m3, rho_d (1 + w)
  double porosity;         // - n = 1 - rho_d / rho_g
  double water_fraction;   // - theta = w rho_d / rho_w
  double saturation;       // - S = theta / n
  double air_voids;        // - n - theta
};

struct SandKeyNumbers {
  double initial_bulk_modulus;        // Pa, loading tangent at zero strain
  double initial_unloading_modulus;   // Pa
  double initial_shear_modulus;       // Pa
  double lockup_pressure;             // Pa, where the air voids close
  double lockup_strain;               // - natural strain -ln(V/V0) at lockup
  double lockup_density;              // kg/m3
  double yield_plateau;               // Pa
  double friction_knee_pressure;      // Pa, where the friction branch meets the plateau
  double loading_wave_speed;          // m/s, sqrt(K_load / rho)
  double elastic_wave_speed;          // m/s, sqrt((K_unload + 4 G / 3) / rho)
  double wood_bulk_modulus;           // Pa, 1/K = (1-n)/K_q + n/K_w (reference for S = 1)
};

struct CurvePoint {
  double pressure;          // Pa
  double strain;            // - engineering volumetric strain 1 - V/V0
  double natural_strain;    // - -ln(V/V0)
  double density;           // kg/m3
  double loading_modulus;   // Pa, -V dp/dV along the loading curve
  double unloading_modulus; // Pa
  double shear_modulus;     // Pa
};

// The air-void skeleton spring, derived once from the dry Sjobo curve by removing the quartz
// compliance: closure fraction e in [0, 1] vs pressure, and its elastic unloading compliance.
class VoidSpring {
 public:
  explicit VoidSpring(const QuartzParams& quartz);
  double closure(double p) const;                 // - fraction of the voids closed
  double compliance(double p) const;              // d closure / dp on loading
  double unloadingCompliance(double p) const;     // d closure / dp on unloading, <= compliance
  double pressureAtClosure(double e) const;
  double lockupPressure() const { return p_lock_; }
  double referencePorosity() const { return n_ref_; }
  bool extrapolatedBeyondTable(double p) const { return p > p_table_end_; }

 private:
  MonotoneCubic curve_;
  std::vector<double> unload_e_, unload_c_;   // knots of the unloading compliance vs closure
  double n_ref_, p_lock_, p_table_end_;
};

class SandModel {
 public:
  explicit SandModel(const SandInputs& in);   // validates; throws InputError naming the field

  const SandInputs& inputs() const { return in_; }
  const SandState& state() const { return state_; }
  const VoidSpring& voidSpring() const { return void_; }

  double strain(double p) const;               // engineering volumetric strain on loading
  double naturalStrain(double p) const;        // -ln(V/V0) on loading
  double pressureAtNaturalStrain(double x) const;
  double loadingModulus(double p) const;       // true tangent -V dp/dV
  double unloadingModulus(double p) const;     // true elastic modulus after loading to p
  double shearModulus(double p) const;         // after loading to p
  double yieldStrength(double p) const;        // bilinear: friction branch, then plateau
  double yieldPlateau() const { return plateau_; }
  // The energy term p_th = gamma T(x) rho0 e. gamma: the constituents' thermal pressure at equal
  // temperature and equal pressure (grains and water in series, Reuss-weighted), per unit of the
  // mixture's energy density: gamma = [sum (phi_k/K_k) G_k rho_k c_k / sum (phi_k/K_k)] / sum phi_k rho_k c_k.
  // T(x) = f(x) e^x with f rising linearly from 0 (as laid) to 1 where the air voids close: heated
  // grains in a porous skeleton expand into its voids, so the skeleton carries their thermal
  // pressure only as the voids close; e^x turns rho0 into the current density.
  double thermalGamma() const { return thermal_gamma_; }
  // Pa: the input cap on the skeleton's shear modulus, or quartz's own
  double shearModulusCap() const { return in_.shear_modulus_cap > 0.0 ? std::min(in_.shear_modulus_cap, in_.quartz.shear_modulus) : in_.quartz.shear_modulus; }
  double thermalFactor(double x) const;
  double maxPressure() const { return p_max_; }   // top of the tabulated range
  SandKeyNumbers keyNumbers() const;
  std::vector<CurvePoint> sampleLoading(int n) const;   // geometric in pressure up to maxPressure
  CurvePoint pointAt(double p) const;

 private:
  double waterStrain(double p) const;
  double compliance(double p, bool unloading) const;

  SandInputs in_;
  SandState state_;
  VoidSpring void_;
  double water_eta_top_;
  double plateau_;
  double thermal_gamma_ = 0.0;
  double lockup_strain_ = 0.0;
  double skeleton_ref_compliance_;
  double p_max_ = 50e9;   // Pa: covers sand driven to quartz density beside a detonating charge
};

// The hydrocode's point evaluator: pressure and bulk modulus from the current natural strain
// x = ln(rho/rho0) and the largest one reached, x_max (loading on the curve, elastic
// unloading and reloading below it, tension cutoff). Precomputed on a uniform strain grid:
// O(1), no allocation, no search per call.
class SandPointEos {
 public:
  struct Result {
    double pressure;       // Pa
    double bulk_modulus;   // Pa, tangent on the branch in use (for the sound speed)
  };

  explicit SandPointEos(const SandModel& model, int table_size = 4096);

  // x: natural strain ln(rho/rho0); x_max: the largest reached; e: specific internal energy, J/kg.
  Result evaluate(double x, double x_max, double e = 0.0) const noexcept {
    Result r = compaction(x, x_max);
    if (e > 0.0 && gamma_ > 0.0) {
      // The energy term, added before the tension cutoff: heated sand that unloads rebounds along
      // its stiff unloading branch until the total pressure falls to zero (a small expansion, like
      // the grains' thermal expansion), instead of the term pushing it back to its laid density.
      const double ex = x > 0.0 ? std::exp(x) : 1.0;
      const double f = x <= 0.0 ? 0.0 : (x >= x_lock_ ? 1.0 : x / x_lock_);
      const double df = x > 0.0 && x < x_lock_ ? 1.0 / x_lock_ : 0.0;
      const double p_th = gamma_ * f * ex * rho0_ * e;
      r.pressure += p_th;
      // rho c^2 = rho dp/drho|e + (p / rho) dp/de: the term's own stiffness d p_th / dx, and its
      // energy derivative gamma f rho0 e^x / rho = gamma f
      r.bulk_modulus += p_th + gamma_ * df * ex * rho0_ * e + (r.pressure > 0.0 ? r.pressure : 0.0) * gamma_ * f;
    }
    if (r.pressure < p_cut_) r.pressure = p_cut_;
    r.pressure += pore_p_;
    return r;
  }

  // The skeleton's shear modulus for the largest natural strain reached and the pressure now (Pa,
  // pore pressure included): by the law of SandInputs::shear_follows_pressure.
  double shearModulus(double x_max, double p) const noexcept {
    if (follow_pressure_) {
      const double pe = p - pore_p_;
      return tableAt(gp_, std::log1p((pe > 0.0 ? pe : 0.0) * kInvShearPressureScale) * inv_du_);
    }
    const double s = x_max * inv_dx_;
    return tableAt(g_, s < 0.0 ? 0.0 : s);
  }
  double referenceDensity() const { return rho0_; }
  double tensionCutoff() const { return p_cut_ + pore_p_; }   // Pa, the lowest pressure (pore pressure included)
  double porePressure() const { return pore_p_; }
  double thermalGamma() const { return gamma_; }
  double tableTop() const { return dx_ * last_ + dx_; }

 private:
  // The compaction curve's pressure (loading, or elastic unloading below x_max), before the cutoff.
  Result compaction(double x, double x_max) const noexcept {
    const bool loading = x >= x_max;
    const double xl = loading ? x : x_max;
    double s = xl * inv_dx_;
    s = s < 0.0 ? 0.0 : s;
    int i = static_cast<int>(s);
    i = i > last_ ? last_ : i;
    const double t = s - i;   // t > 1 extrapolates the last interval
    const double p_on_curve = xl < 0.0 ? k_load_[0] * xl : p_[i] + t * (p_[i + 1] - p_[i]);
    if (loading) {
      const double k = k_load_[i] + (t > 1.0 ? 1.0 : t) * (k_load_[i + 1] - k_load_[i]);
      return {p_on_curve, k};
    }
    const double k = k_unload_[i] + (t > 1.0 ? 1.0 : t) * (k_unload_[i + 1] - k_unload_[i]);
    const double p = p_on_curve - k * (x_max - x);
    return {p, k};
  }

  // A table at the fractional node s >= 0, held at its last value past the end.
  double tableAt(const std::vector<double>& v, double s) const noexcept {
    int i = static_cast<int>(s);
    i = i > last_ ? last_ : i;
    const double t = s - i;
    return v[static_cast<std::size_t>(i)] + (t > 1.0 ? 1.0 : t) * (v[static_cast<std::size_t>(i) + 1] - v[static_cast<std::size_t>(i)]);
  }

  std::vector<double> p_, k_load_, k_unload_, g_;
  // the shear modulus by effective pressure, on u = ln(1 + p / 1 MPa) uniform (to the curve's top)
  static constexpr double kInvShearPressureScale = 1e-6;   // 1/Pa
  std::vector<double> gp_;
  double inv_du_ = 1.0;
  bool follow_pressure_ = false;
  double dx_, inv_dx_, rho0_, p_cut_;
  double pore_p_ = 0.0;   // Pa, SandInputs::pore_pressure
  double gamma_ = 0.0, x_lock_ = 1.0;   // energy term (SandModel::thermalGamma, thermalFactor)
  int last_;
};

}  // namespace ejecta::materials
