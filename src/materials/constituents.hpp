#pragma once
// Constituents of wet sand: quartz grains, pore water, and the dry Sjobo sand baseline.
// Sources and status (verified = read in a stored copy, recalled = still to be checked) are
// those of shared/data/*.csv; they are echoed in every JSON output of the sand model.
#include <array>
#include <string>

namespace ejecta::materials {

// Quartz grains. Murnaghan compression V/V0 = (1 + K' p / K0)^(-1/K').
struct QuartzParams {
  double grain_density = 2650.0;   // kg/m3 (verified)
  double bulk_modulus = 36.6e9;    // Pa (verified; 36.0-37 GPa in other sources)
  double dK_dp = 6.0;              // - pressure derivative K'; ours: single-crystal alpha-quartz
                                   //   compression studies give 4-6; sensitivity reported
  double shear_modulus = 45.0e9;   // Pa (verified)
  // Thermal terms, for the sand's energy term only (recalled handbook values, not in shared/data):
  // volumetric expansion 3.5e-5 /K and c_v 740 J/(kg K) give Gruneisen alpha K / (rho c_v) = 0.66.
  double gruneisen = 0.66;             // -
  double heat_capacity = 740.0;        // J/(kg K)

  double strain(double p) const;            // engineering volumetric strain 1 - V/V0 at pressure p
  double compliance(double p) const;        // d strain / dp
};

// Water as a Mie-Gruneisen material in LS-DYNA's form; the spring uses its shock Hugoniot
// p_H(mu) = rho0 C^2 mu (1+mu) / [1 - (S1-1) mu - S2 mu^2/(1+mu) - S3 mu^3/(1+mu)^2]^2,
// which for S2 = S3 = 0 is the linear Us-up Hugoniot p = rho0 C^2 eta / (1 - S1 eta)^2.
struct WaterEosSet {
  std::string name;
  double rho0;    // kg/m3
  double c0;      // m/s
  double s1, s2, s3;
  double gamma0;  // -
  const char* status;

  double hugoniotPressure(double eta) const;        // eta = 1 - V/V0
  double hugoniotStiffness(double eta) const;       // dp/d eta
  double etaAsymptote() const;                      // eta where the Hugoniot pressure diverges
  double strainAtPressure(double p) const;          // inverse of hugoniotPressure
  double bulkModulus() const { return rho0 * c0 * c0; }
};

WaterEosSet waterAwg();   // LS-DYNA Aerospace Working Group set (verified): C=1500, S1=1.75, g0=0.28
WaterEosSet waterAlt();   // alternative set (recalled): C=1647, S1=1.921, S2=-0.096, g0=0.35
WaterEosSet waterEosByName(const std::string& name);  // "awg" or "alt"; throws InputError

// Dry Sjobo sand, Laine & Sandvik (2001): uniaxial-strain compaction and unloading sound speed.
struct SjoboRow {
  double density;        // kg/m3
  double pressure;       // Pa
  double sound_speed;    // m/s, elastic unloading
  bool pressure_verified;
};
inline constexpr double kSjoboDensity = 1674.0;            // kg/m3, loose reference density
inline constexpr double kSjoboShearModulus = 76.9e6;        // Pa at 1674 kg/m3 (verified)
inline constexpr double kSjoboPoisson = 0.22;               // - (verified)
inline constexpr double kSjoboFrictionSlope = 1.396;        // dY/dp (verified)
inline constexpr double kSjoboTensionCutoff = -6.9e3;       // Pa (verified)
// The unloading sound speeds are recalled (provisional), see sjobo_sand_unloading.csv.
inline constexpr std::array<SjoboRow, 10> kSjoboTable{{
    {1674.0, 0.0, 265.2, true},
    {1740.0, 4.577e6, 852.1, false},
    {1874.0, 14.98e6, 1721.7, true},
    {1997.0, 29.15e6, 2264.4, true},
    {2144.0, 58.18e6, 2945.7, true},
    {2250.0, 98.10e6, 3154.8, true},
    {2380.0, 179.44e6, 3386.4, true},
    {2485.0, 289.44e6, 3653.0, true},
    {2585.0, 450.20e6, 4351.3, true},
    {2671.0, 650.66e6, 4616.5, true},
}};

}  // namespace ejecta::materials
