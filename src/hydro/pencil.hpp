#pragma once
// The kernels of one directional sweep, each on one pencil (a 1D line of cells along the sweep
// axis, ghosts included), in the order the solver calls them:
//   gather (Solver)  ->  computeSlopes  ->  solveFaces  ->  lagrangeUpdate (closeMixedCell per
//   mixed cell)  ->  remapFluxes  ->  scatter (Solver).
// They see flat arrays only: no files, no MPI, no mesh. Every joule they move is booked: what
// crosses the pencil's two end faces (`PencilLedger::boundary_in`), the work done on a moving
// wall (`target_work`), and gravity's work (`gravity_work`).
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace ejecta::hydro {

inline constexpr double kAlphaMin = 1e-8;      // below this a material is a fragment: it rides along
inline constexpr double kPureCell = 1.0 - 1e-9;
inline constexpr int kMaxMaterials = 8;
// The body's load is also split by the materials' volume within these distances of each wall face
// (m), besides the material in the cell beside it: a film one cell thick is a different share of
// the load at every cell size, a layer of fixed depth is not (docs/run.md, "The load by material").
inline constexpr int kNearWallDepths = 3;
inline constexpr std::array<double, kNearWallDepths> kNearWallDepth_m = {0.01, 0.02, 0.04};

// Per-thread scratch of one pencil. Per-material arrays are [k * N + i] (cells) or
// [k * (N + 1) + f] (faces); face f lies between cells f - 1 and f.
struct Pencil {
  int n = 0, N = 0, M = 0;   // interior cells, cells with ghosts, materials
  // The run's index of each of the pencil's materials. A sweep carries only the materials present
  // somewhere in the pencil, ghosts included (no other can enter it in the sweep), so that a pencil
  // of pure air or pure sand does one material's work after a scan of each material's fractions.
  // The body's load is booked by the run's index.
  int mat[kMaxMaterials] = {};
  // A material without strength (gas, products, water) carries no deviatoric stress: its stress
  // (`s`) and stress fluxes (`fs`) are neither written nor read, and the body's friction does not act
  // on its share of a contact. False (the default) carries them and grips (Solver::selectMaterials
  // sets it for every pencil of a run).
  bool strengthless[kMaxMaterials] = {};
  bool radial = false;       // axisymmetric or spherical r-sweep: swept volumes are annuli or shells
  bool spherical = false;    // spherical r-sweep: volumes r^3 / 3 per steradian
  double ring_width = 0.0;   // axisymmetric r-sweep: the cell's z width
  std::vector<double> vol, area;
  std::array<std::vector<double>, 3> u;   // velocity components (global axes)
  std::vector<double> rho, P, K, Z, hoop;
  // The stiffness (rho c^2) the MUSCL-Hancock predictor advances the normal and hoop stresses with:
  // K itself in a cell of one material (fragments aside); in a mixed cell the mixture's Reuss (Wood)
  // modulus 1 / sum(alpha_k / K_k) over the materials above kAlphaMin, the stiffness the closure
  // gives the cell (closeMixedCell shares a volume change by compressibility). K is the Voigt sum,
  // which in products carrying a dust of sand is the sand's: half a step of it took the face
  // pressure of an expanding dusty cell far below the cell's own, by an amount proportional to the
  // step (docs/solver.md, The predictor).
  std::vector<double> Kp;
  // mixture_reuss only: a mixed cell's shock slope (kg/m3), its impedance under a compression du
  // being Z + zs du; rho_mix over the fraction of its volume that takes a compression (`soft`, the
  // gather's sum alpha^2 / K until it is used); 0 in a cell of one material.
  std::vector<double> zs, soft;
  std::vector<double> zmax;      // mixture_reuss only: the ceiling of Z + zs du, the frozen sum's impedance (at least Z)
  std::vector<double> p_per_k;   // mixture_reuss only: the gather's sum alpha_k p_k / K_k over the materials above kAlphaMin
  std::vector<double> pmin;                   // the cell's tension limit (volume weighted): a wall's floor
  std::array<std::vector<double>, 2> shear;   // mixture s_{d,t} for the two transverse axes
  std::vector<double> a, r, e, h, pk, kk, wl;   // per material: alpha, rho, e, history, p, rho c^2, WLIC weight
  // per material: THINC's profile at a cell's low and high faces (the cell's fraction where it has none), for BVD
  std::vector<double> tlo, thi;
  std::array<std::vector<double>, 6> s;
  // faces
  std::vector<double> ustar, pstar, dvol;
  // Lagrangian cells
  std::vector<double> vlag, mass, ke;
  std::array<std::vector<double>, 3> mom;
  std::vector<double> vk, mk, iek;
  std::vector<double> sum_snn, sum_s11;        // the gather's mixture sums of two stress components
  std::vector<double> ie_cell, die, w_grav;   // the cell's internal energy, its change, gravity's work
  std::vector<double> present;   // how many materials are above kAlphaMin in the cell (a double: the loops that count it vectorise)
  // remap fluxes at faces (signed, + along the axis)
  std::vector<double> fv, fm, fe, fh, fkek;   // per material: volume, mass, internal energy, history, kinetic energy
  std::array<std::vector<double>, 6> fs;
  std::array<std::vector<double>, 3> fmom;
  std::vector<double> su, sp;   // limited slopes of normal velocity and normal stress
  // An r-sweep's rate of volume change per unit volume that the predictor takes, 1/s: su plus
  // u / r (axisymmetric) or 2 u / r (spherical), the swept annuli's and shells' growth (elsewhere
  // the predictor takes su itself).
  std::vector<double> dil;
  std::vector<unsigned char> solid;

  void resize(int cells, int materials);
  std::size_t at(int k, int i) const { return static_cast<std::size_t>(k * N + i); }
  std::size_t atFace(int k, int f) const { return static_cast<std::size_t>(k * (N + 1) + f); }
};

// What one sweep needs besides the pencil: the axis, the step, the line's geometry (the same
// for every pencil: centres, widths, faces, inverse centre spacings) and the moving wall.
struct SweepSetup {
  int d = 0, t1 = 1, t2 = 2;   // sweep axis and the two transverse axes
  int materials = 0;           // the run's materials (a pencil carries those present in it: Pencil::mat); 0: the pencil's
  double dt = 0.0;             // s
  bool second_order = true;
  double thinc_beta = 3.5;
  bool thinc_bvd = false;      // SolverOptions::thinc_bvd
  double gravity = 0.0;        // m/s2 along d
  std::array<double, 3> wall_velocity{};   // m/s, the body's
  double friction = 0.0;       // - Coulomb coefficient at the body's faces
  double load_reference = 0.0; // Pa: the body's load by material is booked as (p* - this) A dt
  const double* xc = nullptr;  // [N]
  const double* width = nullptr;   // [N]
  const double* xf = nullptr;  // [N + 1]
  const double* inv_dx = nullptr;  // [N], 1 / (xc[i] - xc[i-1])
  const double* grid_disp = nullptr;   // [N + 1], m: how far each face moves this sweep (a body moving the mesh; else 0)
  // The pencil's end faces are the domain's boundary (their energy flow is booked); false where a
  // slab of the domain meets its neighbour (the face is interior to the whole).
  bool lo_is_boundary = true, hi_is_boundary = true;
  // Where an end is the domain's boundary, whether its ghosts copy the boundary cell (an outflow
  // side) rather than mirror the interior (a reflecting wall, the axis).
  bool lo_ghosts_copy = false, hi_ghosts_copy = false;
  bool mixture_reuss = false;   // SolverOptions::mixture_reuss: the faces' shock impedance (Pencil::zs)
};

// Energy booked by one pencil in one sweep, J (axisymmetric: per radian).
struct PencilLedger {
  double boundary_in = 0.0;    // across the pencil's two end faces, into the block
  double target_work = 0.0;    // done by the flow on the moving body
  double gravity_work = 0.0;   // done by gravity on the flow
  double folded_mass[kMaxMaterials] = {};          // kg by the run's material index (Solver::scatterPencil)
  double boundary_mass[kMaxMaterials] = {};        // kg by the run's material index, into the block across the end faces
  double impulse_total[3] = {};                    // N s: the load itself (normal stress and friction)
  double impulse_on_body[kMaxMaterials][3] = {};   // N s by material beside the face: the normal load
                                                   // (along d, against the reference pressure, which
                                                   // sums to zero over a closed body) and the friction
  double impulse_near_body[kNearWallDepths][kMaxMaterials][3] = {};   // the same, by material within
                                                                      // kNearWallDepth_m of the face
  // A domain split into slabs sums the body's load in the whole's order: each increment above is
  // also logged, in order, as [key, component, total, by material (M), near the wall (3 M)]
  // (`kBodyEventSize`), when `events` is set; `key` is the pencil's place in the whole's order.
  std::vector<double>* events = nullptr;
  double key = 0.0;
  // Every book back to zero; `events` and `key` stay (a ledger is reused from sweep to sweep).
  void clearBooks() {
    auto* const ev = events;
    const double k = key;
    *this = PencilLedger{};
    events = ev;
    key = k;
  }
};
inline constexpr int bodyEventSize(int M) { return 3 + (1 + kNearWallDepths) * M; }

// Each material's share of the fluid within `depth` (m) of a wall face, from the fluid cell `from`
// beside it walking away from the body by `step` (+1 or -1) over interior fluid cells: by volume,
// the last cell by the part of its width inside the depth; at least the cell beside the face.
// `share` sums to 1.
void nearWallShares(const Pencil& P, const SweepSetup& S, int from, int step, double depth, double* share);

// van Leer-limited slopes of the normal velocity and normal stress (first order beside a body),
// and in an r-sweep the dilatation rate the predictor takes (Pencil::dil).
void computeSlopes(Pencil& P, const SweepSetup& S);

// Acoustic Riemann problem (Z = rho c) with MUSCL-Hancock states at faces 1 .. N-1: face
// velocity u*, normal stress p*, swept volume. The states are advanced by half a step with the
// predictor's stiffness (Pencil::Kp) and dilatation rate; in an r-sweep P.hoop is advanced to the
// same half step (once a sweep), since the Lagrange phase balances it against the face stresses.
// A face beside the body is a wall moving with it: the flow's half of the Riemann problem, never
// below the flow cell's tension limit (a wall that the flow leaves cannot pull it back), no swept
// volume; its load goes to `ledger`.
void solveFaces(Pencil& P, const SweepSetup& S, PencilLedger& ledger);

// Lagrange phase of cells 1 .. N-2: momentum and total energy in flux form, volumes moved,
// the volume change and heat shared among materials (closeMixedCell).
void lagrangeUpdate(Pencil& P, const SweepSetup& S, PencilLedger& ledger);

// One mixed cell's closure after the Lagrange phase. In: each material's alpha, pressure,
// rho c^2, mass, internal energy (J) before, the cell's volumes before (V) and after (Vl), and
// the cell's internal energy change `die` (J). Out: each material's volume and internal energy.
//  1. The volume change is shared by compressibility alpha_k / (rho_k c_k^2) (equal pressure
//     increments), no material losing more than 95% of its volume in a step (the rest goes to the
//     others); each material's work for the change it makes follows its local polytrope (a
//     stiff material compressed: the trapezoid, at its mean pressure).
//  2. Materials at unequal pressures (after step 1's change) exchange volume towards their
//     linearised common pressure p_eq, every one working at p_eq: no heat is routed between them.
//  3. The rest of `die` (the Riemann solver's dissipation, shear work) goes to the materials in
//     proportion to their compression in this step (by |p dV| where none was compressed), at most
//     twice the cell's mean per unit mass each, the remainder by mass; a loss is taken in
//     proportion to the internal energy each holds. Total energy is exact.
struct MixedCell {
  int M = 0;
  double alpha[kMaxMaterials], p[kMaxMaterials], K[kMaxMaterials], m[kMaxMaterials], ie[kMaxMaterials];
  double v[kMaxMaterials];   // out: volumes, summing to Vl
};
// Work on a material of volume v0 at pressure p, bulk modulus K, whose volume changes by dv (J):
// along the local polytrope p v^(K/p) = const (a stiff material compressed: the trapezoid).
double volumeWork(double p, double K, double v0, double dv);
void closeMixedCell(MixedCell& c, double V, double Vl, double die);

// Remap fluxes through faces g .. g+n, onto the faces moved by S.grid_disp (the Lagrangian face's
// overshoot of the moved face is what crosses it; nothing crosses a face beside the body, which
// moves with it): each material's volume (THINC profile weighted by the
// interface orientation), mass, energy, history and stress at donor values (limited slopes in
// pure regions), momentum with limited slopes, and each material's kinetic energy.
void remapFluxes(Pencil& P, const SweepSetup& S, PencilLedger& ledger);

// The cells' volumes on the moved faces (after remapFluxes, before the scatter): V + A (dz_R - dz_L),
// which is the Lagrangian volume less what the remap moved out.
void moveCellVolumes(Pencil& P, const SweepSetup& S);
// Kinetic energy that a remap (or a rezone) took from the flow, returned as heat: `heat` in all
// (sum of `loss` plus anything else to place), to each material as it lost it, but never more
// than twice the cell's mean heat per unit mass (a sliver whose in- and outflow nearly cancel
// has an ill-defined loss); what that leaves goes by mass. A net gain (heat < 0, possible with
// limited slopes) is taken in proportion to the internal energy each material holds (`held`, J).
// `add[k]` sums to `heat` exactly.
void shareHeat(int M, const double* mass, const double* loss, double heat, const double* held, double* add);

// Fragments of one cell (docs/solver.md, Fragments): each material under `cut` of the cell's volume
// `vs` gives its volume `vk`, mass `mk` and internal energy `ie` (J) to the others, by their
// volumes, and ends with all three zero; if one material is left its volume is `vs` exactly.
// `folded[k]` (kg) is what material k gave, or minus what it took (exactly its mass's change).
// The sums of mass and energy stay to round-off. Call with at least two materials holding mass.
void foldFragments(int M, double cut, double vs, double* vk, double* mk, double* ie, double* folded);

// Fraction of the donor's volume that is material k and leaves through the face, for a swept
// fraction b of the donor, from a THINC (tanh) profile (Xiao, Honma & Kono 2005).
double thincOutflow(double a, double a_lo, double a_hi, double b, bool out_high, double beta);
// The same with the profile's constants computed once (exp(beta) and exp(-beta): a remap asks at
// every face of every mixed cell); the same number to the bit.
struct ThincProfile {
  explicit ThincProfile(double b) : beta(b), exp_beta(std::exp(b)), exp_minus_beta(std::exp(-b)) {}
  double beta, exp_beta, exp_minus_beta;
};
double thincOutflow(double a, double a_lo, double a_hi, double b, bool out_high, const ThincProfile& profile);
// x / d for several x: products by 1 / d, taken once (a divider is far slower than a multiplier),
// or the quotients themselves where d is subnormal and its reciprocal not finite.
struct Reciprocal {
  explicit Reciprocal(double divisor) : d(divisor), inv(1.0 / divisor), finite(std::isfinite(inv)) {}
  double of(double x) const { return finite ? x * inv : x / d; }
  double d, inv;
  bool finite;
};

// One face of a remap: the swept fraction, the side it leaves by, and the profile's exponential of
// the face (exp(beta (1 - b)) through the high face, exp(beta b) through the low one), taken once
// when a material first needs it and then shared by the face's other materials.
struct ThincFace {
  ThincFace(double swept, bool high, const ThincProfile& profile) : b(swept), out_high(high), th(profile) {}
  double exponential() {
    if (!(e > 0.0)) e = std::exp(th.beta * (out_high ? 1.0 - b : b));
    return e;
  }
  double b;
  bool out_high;
  ThincProfile th;   // a copy (three numbers): a face never outlives its profile's temporary
  double e = 0.0;
};
double thincOutflow(double a, double a_lo, double a_hi, ThincFace& face);
void thincFaceValues(Pencil& P, int i0, int i1, const ThincProfile& th);
bool bvdTakesTheProfile(const Pencil& P, std::size_t c);

}  // namespace ejecta::hydro
