#pragma once
// The multi-material Eulerian solver: cell-centred, directionally split Lagrange + remap.
//
// Each step sweeps the axes in turn (x y z, then z y x: Strang alternation). A sweep works on
// independent 1D pencils of cells:
//   1. Lagrange: an acoustic Riemann solver with MUSCL-Hancock states gives each face a velocity
//      and a normal stress; cells move, compress and do work (axisymmetric hoop term included).
//      In a mixed cell the volume change is shared in proportion to each material's
//      compressibility and the dissipation by mass, so air, products and sand stay stable.
//   2. Remap: the moved faces are swept back. Each material's volume crosses a face according to
//      a THINC profile (a sharp, conservative interface); mass, energy, history and stress go with
//      it at donor values (limited slopes in pure regions); momentum with limited slopes; the
//      kinetic energy the remap removes is returned as heat, so total energy is conserved.
// Deviatoric stress is updated once per step (hypoelastic, Jaumann rotation, radial return to
// the yield surface). Mass and momentum are conserved to round-off; total energy is tracked.
//
// Kernels see only flat arrays and a grid: no files, no MPI. Pencils are independent, so OpenMP
// threads share them now, and MPI ranks (a block plus ghost layers) and a GPU can later.
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <iosfwd>
#include <string>
#include <vector>

#include "materials/material.hpp"
#include "hydro/pencil.hpp"
#include "mesh/grid.hpp"
#include "parallel/loops.hpp"

namespace ejecta::parallel {
class Exchange;   // parallel/exchange.hpp
}

namespace ejecta::hydro {

using Vec3 = std::array<double, 3>;

struct DetonationPoint {
  Vec3 position{};   // m
  double time = 0.0; // s, when it lights
};

// Revision of the numerics: raised whenever a change alters results (2: products' adiabat;
// 3: no adiabat, energy conserved with a ledger, mixed-cell heat by compression, the sand's energy
// term; 4: mixed-cell work along each material's polytrope, relaxation heat capped per unit mass;
// 5: a wall's load never below the tension limit of the flow beside it, a free target moves the mesh;
// 6: 3D runs take the axisymmetric early time; 2D results are revision 5's; 7: mixed-cell
// relaxation at the common pressure of the pressures after the volume change, nothing routed;
// 8: fragments under SolverOptions::fragment_fold folded into their cells' other materials;
// 9: outflow boundaries let no detonation products back in, SolverOptions::inflow_barred;
// 10: the MUSCL-Hancock predictor advances a mixed cell's stresses with its Reuss modulus
// (Pencil::Kp), an r-sweep's with the whole dilatation, and the hoop stress to the same half step).
// 11: the sand's shear modulus follows the effective pressure now (was: the largest compaction
// seen) and is bounded by a Poisson's ratio of 0.22 on the unloading bulk modulus (docs/sand-model.md).
// 12: the body's Coulomb friction acts on the share of the contact held by materials with strength
// (the sand), not on gas, products or water, which carry no shear stress; it opposes the slide in
// the face's plane as one traction (was: each transverse component alone); its load by material is
// booked to the sand, by the cell beside the face at every depth (docs/run.md, The plate).
// 13: the time step takes a cell's frozen (Voigt) mixture speed alone; a material's own speed no
// longer counts where it holds 1% of the cell's mass (docs/solver.md, "Revision 13: the step of a
// mixed cell").
// 14: the same physics in fewer operations, results moved at round-off (grown to 0.2% over a 10 ms
// 3D run; docs/validate.md): THINC's flux as the log of one ratio (an exp and a log per material
// plus an exp per face shared by its materials, where six calls per material were made), one power
// per gas in the mixed-cell closure (step 1's polytrope serves step 2's pressure), quotients taken
// once in the closure, and products by a reciprocal in the remap, the scatter and the interface
// weights (docs/solver.md, "Revision 14").
// `ejecta validate --reuse` reruns a case saved by another revision; a checkpoint of another
// revision is refused (its energy books differ in layout too).
// 15: a mixed cell's stiffness in the faces' impedance and the time step is by default the one the
// closure answers with (Reuss with its dilution stiffness, `mixture_stiffness = "reuss"`), at
// Courant 0.30 (the default was the frozen Voigt sum at 0.45); the ghosts along a sweep's axis take
// their source cells' WLIC weights (docs/solver.md, "Revision 15").
inline constexpr int kSolverRevision = 15;

inline constexpr int kMaxSweepTile = 64;   // the widest tile of pencils a sweep takes (SolverOptions::sweep_tile)

struct SolverOptions {
  // - Courant number of each sweep: 0.30 since revision 15, chosen by the Reuss step's own error
  // (docs/solver.md, "Revision 15"; 0.45 before, with the frozen stiffness)
  double cfl = 0.30;
  Vec3 gravity{0.0, 0.0, 0.0};           // m/s2
  // Boundaries: [axis][0 = low, 1 = high].
  std::array<std::array<mesh::BoundaryKind, 2>, 3> boundary{};
  std::vector<DetonationPoint> detonation;
  bool second_order = true;              // MUSCL-Hancock faces and limited remap slopes
  double thinc_beta = 3.5;               // - THINC interface sharpness
  double max_dt = 1.0;                   // s
  double min_dt = 1e-14;                 // s: below this the step has collapsed and the run stops
  double initial_dt_fraction = 0.1;      // first step = this fraction of the CFL step
  // A mixed cell's stiffness in the faces' impedance and the time step (docs/solver.md, "The
  // mixture's stiffness"). Reuss (default since revision 15): what the closure's volume sharing
  // answers with, 1 / sum (alpha_k / K_k), plus the dilution stiffness of a cell out of pressure
  // equilibrium, with a shock impedance floor rho |du| / alpha_soft and a step that sees the soft
  // fraction closing. Frozen: sum alpha_k K_k, the Voigt sum, which in a gas carrying a dust of sand
  // is the sand's (the default up to revision 14).
  bool mixture_reuss = true;
  // THINC's profile on an interface (near-pure fractions on both sides within two cells), elsewhere
  // only where it leaves smaller jumps at the donor's faces than the donor mean (BVD; docs/solver.md,
  // "Interfaces and dust"): a dust of sand in gas is remapped by the mean, not striped.
  // Experimental: off by default; on the mesh study it moves the impulse by +0.9 to +1.5%.
  bool thinc_bvd = false;
  double body_friction = 0.0;            // - Coulomb coefficient between the sand and the body (gas slides freely)
  double load_reference_pressure = 0.0;  // Pa: the body's load by material is booked against it (ambient)
  // Every pencil carries every material, not only those present in it (Pencil::mat): the same
  // result to the bit, slower; kept so that a test can hold the two against each other.
  bool carry_all_materials = false;
  // Pencils swept together along a strided axis: their cells are read into a tile's scratch once,
  // a cache line serving all its pencils (1: each pencil reads the mesh itself). The same result to
  // the bit at any width; a test holds 1 against the default.
  int sweep_tile = 8;                    // at most kMaxSweepTile
  // A material below this fraction of a cell's volume is folded into the cell's other materials
  // (volume, mass and internal energy, by their volumes; the cell's mass, momentum and energy
  // stay, and EnergyLedger::folded_mass books what each material gave). 0: never. At most
  // kAlphaMin, below which a material only rides along (docs/solver.md, Fragments).
  double fragment_fold = 1e-10;
  // Materials an outflow (Transmit) boundary does not let back in. A zero-gradient ghost stands for
  // a medium that goes on past the boundary (the atmosphere, the ground); the products are a finite
  // mass the run made, and the copy would draw them in without end wherever the flow turns inward.
  // Where it does, a barred material's share of a ghost cell is filled with `inflow_fill` (an ideal
  // gas, the ambient air) at the barred material's pressure, on the gas's isentrope through
  // (inflow_fill_rho, inflow_fill_p): the ghost's pressure and velocity stay the copy's.
  std::vector<int> inflow_barred;
  int inflow_fill = 0;
  double inflow_fill_rho = 1.225;        // kg/m3
  double inflow_fill_p = 101325.0;       // Pa
};

// One material's fields over the block (ghosts included), flat arrays.
struct MaterialFields {
  std::vector<double> alpha, rho, e, h0;        // -, kg/m3, J/kg, history (burn fraction or x_max)
  std::array<std::vector<double>, 6> s;         // Pa, deviatoric stress xx yy zz xy yz xz (if strength)
  void clearCell(std::size_t c) {               // the material has left cell c
    alpha[c] = e[c] = h0[c] = 0.0;
    if (!s[0].empty())
      for (auto& sc : s) sc[c] = 0.0;
  }
};

// Energy that crossed the block's edges since the start, J (axisymmetric: per radian). With the
// energy held in the cells it closes the books: E(t) = E(0) + boundary_in - target_work + gravity_work.
struct EnergyLedger {
  double boundary_in = 0.0;    // through the block's boundary faces (outflow negative)
  double target_work = 0.0;    // work done by the flow on the moving body
  double gravity_work = 0.0;   // work done by gravity on the flow
  // kg by material (the run's order): the mass it gave to other materials by folding its fragments,
  // less what it took from theirs. The mass books close with it: held + folded = initial + inflow.
  std::array<double, kMaxMaterials> folded_mass{};
  // kg by material: what crossed the block's boundary faces, inward positive (revision 9). The mass
  // books of an open run close with it: held + folded = initial + boundary_mass.
  std::array<double, kMaxMaterials> boundary_mass{};
  EnergyLedger scaled(double f) const {   // the books of a run mapped onto f times its volume
    EnergyLedger l{f * boundary_in, f * target_work, f * gravity_work, {}, {}};
    for (std::size_t k = 0; k < folded_mass.size(); ++k) {
      l.folded_mass[k] = f * folded_mass[k];
      l.boundary_mass[k] = f * boundary_mass[k];
    }
    return l;
  }
};

struct Totals {
  std::vector<double> mass;      // kg per material (axisymmetric: per radian)
  Vec3 momentum{};               // kg m/s
  double internal_energy = 0.0;  // J
  double kinetic_energy = 0.0;   // J
  std::vector<double> internal_by_material, kinetic_by_material;   // J
  double boundary_in = 0.0, target_work = 0.0, gravity_work = 0.0;  // J, EnergyLedger so far
  std::vector<double> folded_mass;   // kg per material, EnergyLedger::folded_mass so far
  std::vector<double> boundary_mass; // kg per material, EnergyLedger::boundary_mass so far (inward positive)
  // Material k's mass traced back to the start: held, plus what it folded into others, less what
  // came in across the boundaries; the mass books close when this stays at its initial value.
  double massBooks(std::size_t k) const { return mass[k] + folded_mass[k] - boundary_mass[k]; }
  double total() const { return internal_energy + kinetic_energy; }   // held in the cells
  // What the cells should hold given E0 = total() at the start: E0 + inflow - work + gravity.
  double accounted(double e0) const { return e0 + boundary_in - target_work + gravity_work; }
};

// Statistics of a run so far, for progress lines and summaries.
struct RunStats {
  std::int64_t steps = 0;
  double cell_updates = 0.0;
  double wall_seconds = 0.0;
  std::int64_t staged_tiles = 0;   // tiles of pencils swept through a staged copy (SolverOptions::sweep_tile), since construction or restart
};


struct Pencil;       // hydro/pencil.hpp: the sweep's kernels
struct SweepSetup;

class Solver {
 public:
  Solver(mesh::Grid grid, std::vector<materials::Material> materials, SolverOptions options);

  // --- set-up ---------------------------------------------------------------------------------
  // Fills the region `inside` (sampled `sub` times per axis in each cell, volume weighted) with
  // material `mat` at density rho, specific internal energy e and velocity u. Call for the
  // background (material 0) first. What gives way: every material already there in proportion
  // (`everything`: a region painted over others, a charge in its soil), or the background alone
  // (`background`: regions that do not overlap one another, such as soil layers, so that a cell
  // cut by the boundary between two layers holds the two and no background).
  enum class Over { everything, background };
  void paint(int mat, const std::function<bool(const Vec3&)>& inside, double rho, double e, Vec3 u = {}, int sub = 4, Over over = Over::everything);
  void setVelocity(std::size_t cell, Vec3 u);
  void setSpecificEnergy(int mat, std::size_t cell, double e);
  // Direct access for set-up code that builds states cell by cell (initial conditions only).
  MaterialFields& fieldForSetup(int mat) { return fields_[static_cast<std::size_t>(mat)]; }

  // --- a rigid body (the target) -----------------------------------------------------------------
  // Cells whose centre is inside the body become walls that move with the body's velocity: no
  // material enters them; the normal stress the flow exerts on their faces (from the same Riemann
  // solver) is the load, and the flow gets the opposite momentum, so momentum is conserved exactly.
  void setBody(const std::function<bool(const Vec3&)>& inside);
  // The body moves through the flow along `axis` and carries the mesh with it (an ALE region): the
  // faces from the one nearest `anchor_below` (m) up to the body's lowest face stretch linearly,
  // the body's band of faces translates with it, and the faces from its highest face up to the one
  // nearest `anchor_above` close up linearly; the rest stay. The body's faces stay mesh faces, so
  // the gap beneath a rising plate opens in the mesh and the flow in it expands. Each sweep along
  // `axis` remaps onto the moved faces. Call after setBody. Without it the body stays where it is.
  void moveMeshWithBody(int axis, double anchor_below, double anchor_above);
  double bodyOffset() const { return body_offset_; }   // m, how far the body (and its mesh) has moved
  void setBodyVelocity(Vec3 v) { body_velocity_ = v; }
  bool isBody(std::size_t cell) const { return !body_.empty() && body_[cell] != 0; }
  // Impulse given to the body during the last step, N s (axisymmetric: per radian), in total and
  // by material (the material of the flow cell beside each face, by volume fraction).
  const Vec3& lastBodyImpulse() const { return body_impulse_; }
  // The force (N; axisymmetric: per radian) the flow exerts on the body in the current state: the
  // same wall Riemann problem as a step's faces, without stepping (the load at rest, before any wave).
  Vec3 bodyLoad() const;
  const std::vector<Vec3>& lastBodyImpulseByMaterial() const { return body_impulse_mat_; }
  // The same split by the materials' volume within kNearWallDepth_m[layer] of each face.
  const std::vector<Vec3>& lastBodyImpulseNearWall(int layer) const { return body_impulse_near_[static_cast<std::size_t>(layer)]; }

  // --- a slab of a decomposed domain ----------------------------------------------------------
  // This solver's grid is one slab (mesh::Grid::slab) of a domain split along axis 0, and `ex`
  // connects it to the others: their ghost layers before each sweep, the smallest time step, and
  // the body's load summed in the whole domain's order, so that every slab steps exactly as the
  // whole would (bit for bit; tests/unit/test_decomposition.cpp). The energy books and totals()
  // stay this slab's own (their sum over the slabs is the whole's to round-off); bodyLoad() on a
  // slab is not its share (it skips faces whose flow cell is in a neighbour): take the whole's,
  // wholeBodyLoad(). Call before the first step. A slab may be built as one (a solver on
  // Grid::slab, painted and mapped onto there) or cut from the whole (slab()).
  void setExchange(parallel::Exchange* ex);
  // bodyLoad() of the whole domain, the same to the bit, on every slab of `ex` (every slab calls it:
  // it swaps the ghost layers and gathers the slabs' faces in the whole's order).
  Vec3 wholeBodyLoad();
  // This solver's slab [begin, end) of axis 0 as a solver of its own, in the same state (its cells,
  // ghosts included, the body, the moving mesh, the clock); the slab holding cell 0 keeps the energy
  // books so far, the others start theirs at zero (so that the slabs' books sum to the whole's).
  Solver slab(int begin, int end) const;
  // This whole solver, on rank 0, takes the state the slabs of `ex` hold now, `mine` being rank 0's:
  // every cell (for a checkpoint), the clock and the mesh, and the energy books summed over the
  // slabs, taken one slab at a time (Exchange::gatherToFirstEach). The other ranks call
  // sendForAssembly with theirs at the same time (rank 0 too where it has no whole to assemble into:
  // what reaches it is dropped); only rank 0 holds the whole.
  void assemble(const Solver& mine, parallel::Exchange& ex);
  static void sendForAssembly(const Solver& mine, parallel::Exchange& ex);

  // --- checkpoints: the whole state, bit for bit ------------------------------------------------
  void writeCheckpoint(std::ostream& os) const;
  void readCheckpoint(std::istream& is);   // throws InputError if it does not fit this set-up

  // --- time stepping --------------------------------------------------------------------------
  // CFL step from the current state (not from two threads at once: it keeps its loop's costs); with
  // mixture_reuss it first fills what the step reads beyond each cell (prepareStepNeighbours).
  double stableTimeStep();
  // The one time-step controller (advanceTo and the run's loops use it): the CFL step, grown by at
  // most 20% from the last step that was not cut short (a step cut to land on `stop`, an output
  // time, does not restart the growth), the first one initial_dt_fraction of it; at most max_dt
  // and what is left to `stop`. Throws RunError naming the limiting cell when it falls below min_dt.
  double nextTimeStep(double stop);
  // The cell that sets the time step, in words (indices, position, its materials' states): for
  // the message when the step collapses.
  std::string describeLimitingCell() const;
  double cellStepTime(int i, int j, int k) const;   // the least over the axes of width / signal speed, s
  void prepareStepNeighbours();                      // the ghosts the step reads (mixture_reuss)
  void step(double dt);                  // one full step (all sweeps); throws RunError on blow-up
  // Continues from a state mapped in from another run (hydro/rezone.hpp): the clock starts at t and
  // the energy books carry what that run booked, so they close over both.
  void startAt(double t, const EnergyLedger& booked);
  // Steps until `t_end`; `on_step` (optional) runs after every step.
  void advanceTo(double t_end, const std::function<void(const Solver&)>& on_step = {});

  // --- state ----------------------------------------------------------------------------------
  const mesh::Grid& grid() const { return grid_; }
  const std::vector<materials::Material>& materials() const { return mats_; }
  int materialCount() const { return static_cast<int>(mats_.size()); }
  double time() const { return time_; }
  const RunStats& stats() const { return stats_; }
  double lastDt() const { return last_dt_; }
  const MaterialFields& field(int mat) const { return fields_[static_cast<std::size_t>(mat)]; }
  const std::vector<double>& velocity(int d) const { return u_[static_cast<std::size_t>(d)]; }

  double density(std::size_t cell) const;              // kg/m3, mixture
  double pressure(std::size_t cell) const;             // Pa, volume-fraction weighted
  double materialPressure(int mat, std::size_t cell) const;
  Totals totals() const;
  // totals() in two steps, so that a domain split into slabs sums the same numbers: the sums of each
  // column of axis 0 (per material: mass, internal, kinetic energy; then the momentum), and the
  // totals of such columns in order (with this solver's energy books).
  std::vector<double> columnTotals() const;
  Totals totalsOf(const std::vector<double>& columns) const;
  const EnergyLedger& energyLedger() const { return energy_; }

 private:
  // What a ghost fill copies: everything (a sweep along the axis reads every field of its
  // ghosts), or all but the deviatoric stresses (the stress update reads the velocity's
  // neighbours, the interface weights of the sweeps after it the fractions', and the inflow bar
  // the states it replaces; no kernel reads a stress ghost before its axis's sweep fills it).
  enum class GhostFill { Everything, StatesAndVelocity };
  void fillGhosts(int d, GhostFill what = GhostFill::Everything);
  void barInflow(int d, int side, const std::vector<std::size_t>& ghosts, const std::vector<std::size_t>& sources);
  static std::vector<double> packForAssembly(const Solver& mine);
  std::vector<double> bodyLoadTerms() const;
  void exchangeHalo(bool weights);   // axis 0's ghost layers from the neighbouring slabs: the state, or the interface weights
  void combineBodyLoad(const std::vector<double>& events);
  void packCell(std::size_t c, std::vector<double>& out) const;   // one cell's state, in the slabs' order
  std::size_t unpackCell(std::size_t c, const std::vector<double>& in, std::size_t at);   // returns the next position   // the body's load of a sweep, summed in the whole's order
  void interfaceWeights(int d);
  void sweep(int d, double dt);
  // Where a pencil's cells are read from, by the run's material index: the mesh's own arrays
  // along the sweep axis (`stride` the axis's), or a tile's staged copy of them (stride 1). The
  // gather reads the same values either way; only the cache lines differ.
  struct PencilSource {
    std::ptrdiff_t stride = 1;
    const double* u[3] = {};
    const unsigned char* solid = nullptr;   // null: no body
    const double* alpha[kMaxMaterials] = {};
    const double* rho[kMaxMaterials] = {};
    const double* e[kMaxMaterials] = {};
    const double* h0[kMaxMaterials] = {};
    const double* wl[kMaxMaterials] = {};   // interface weights (read with several materials only)
    const double* s[kMaxMaterials][6] = {};   // deviatoric stress (materials with strength only)
  };
  // A thread's scratch for a sweep: the pencil, and a tile's cells staged for its pencils.
  struct SweepScratch {
    Pencil pencil;
    std::vector<double> staged;                // [slot][pencil of the tile][cell along the sweep]
    std::vector<unsigned char> staged_solid;   // [pencil of the tile][cell]
    std::vector<PencilSource> sources;         // by pencil of the tile
  };
  PencilSource meshSource(int d, std::size_t base) const;
  void stageTile(SweepScratch& T, int d, const std::size_t* bases, int pencils, int N) const;
  void selectMaterials(Pencil& P, const PencilSource& src) const;
  void gatherPencil(Pencil& P, int d, const PencilSource& src, int a, int b, const SweepSetup& S) const;
  std::size_t scatterPencil(const Pencil& P, int d, std::size_t base, PencilLedger& ledger);
  void updateBurn(double dt);
  void updateStress(double dt);
  void checkCell(std::size_t cell, const char* stage) const;
  mesh::Axis movedAxis(double offset) const;
  void bandMovingMesh();   // the moving axis's faces with the body moved by `offset`
  // A 1D mesh is one pencil: a thread team would only wait at its barriers (which, on cores
  // shared with other processes, cost more than the line's work), so it runs on one thread.
  bool useThreads() const { return grid_.dims() > 1; }

  mesh::Grid grid_;
  std::vector<materials::Material> mats_;
  SolverOptions opt_;
  std::vector<MaterialFields> fields_;
  std::array<std::vector<double>, 3> u_;
  std::vector<unsigned char> body_;     // 1 in the rigid body's cells
  Vec3 body_velocity_{};
  int mesh_axis_ = -1;                   // the axis the body moves the mesh along (-1: it does not)
  std::vector<double> faces0_;           // that axis's faces at offset 0
  int f_lo_ = 0, f_b0_ = 0, f_b1_ = 0, f_hi_ = 0;   // fixed below, body band, fixed above (face indices)
  double body_offset_ = 0.0;             // m
  double anchor_below_ = 0.0, anchor_above_ = 0.0;   // m, where the moving mesh stays put
  Vec3 body_impulse_{};
  std::vector<Vec3> body_impulse_mat_;
  std::array<std::vector<Vec3>, kNearWallDepths> body_impulse_near_;
  std::vector<PencilLedger> ledgers_;   // sweep()'s scratch: one per pencil
  // each threaded loop's cost by block last time: the threads' split (parallel/loops.hpp)
  std::array<parallel::LoadBalance, 3> sweep_balance_;   // by the sweep's axis
  parallel::LoadBalance step_balance_;                    // stableTimeStep (which writes it: one caller at a time)
  parallel::LoadBalance stress_balance_, weights_balance_, burn_balance_;
  std::vector<double> wlic_;             // per material and cell: share of the interface facing axis d (mixed cells only: a full cell's is 1)
  std::vector<double> light_distance_;   // m, to the nearest detonation point (+inf without one)
  std::vector<double> light_delay_;      // s, that point's own lighting time
  std::vector<double> burn_length_;      // m, burn ramp length of the cell
  EnergyLedger energy_;
  double time_ = 0.0;
  double last_dt_ = 0.0;
  double dt_free_ = 0.0;                 // s, the last step the controller chose before any cut
  std::int64_t step_ = 0;
  RunStats stats_;
  bool any_strength_ = false;
  parallel::Exchange* exchange_ = nullptr;
  bool halo_lo_ = false, halo_hi_ = false;   // a neighbouring slab below / above along axis 0
  // fillGhosts' lists by axis and side: a boundary's ghost cells and the cells they copy, built on
  // first use (the grid's shape never changes; slab() clears them for the slab's own)
  std::array<std::array<std::vector<std::size_t>, 2>, 3> ghost_dst_, ghost_src_;
  std::array<std::array<parallel::LoadBalance, 2>, 3> ghost_balance_;
};

// Index of the deviatoric component shared by axes a and b (a == b: the normal component).
inline int stressIndex(int a, int b) {
  if (a == b) return a;
  const int lo = a < b ? a : b, hi = a < b ? b : a;
  return lo == 0 ? (hi == 1 ? 3 : 5) : 4;
}

}  // namespace ejecta::hydro
