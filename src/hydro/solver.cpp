#include "hydro/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <istream>
#include <limits>
#include <optional>
#include <ostream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "hydro/pencil.hpp"
#include "parallel/exchange.hpp"
#include "parallel/loops.hpp"

namespace ejecta::hydro {

using materials::EosKind;
using materials::StrengthKind;
using mesh::BoundaryKind;
using mesh::kGhost;

Solver::Solver(mesh::Grid grid, std::vector<materials::Material> materials, SolverOptions options)
    : grid_(std::move(grid)), mats_(std::move(materials)), opt_(std::move(options)) {
  if (mats_.empty() || mats_.size() > 8) throw InputError("materials", fmt::format("{} given; valid 1 to 8", mats_.size()));
  for (const auto& m : mats_) {
    m.validate();
    any_strength_ = any_strength_ || m.hasStrength();
  }
  if (!(opt_.cfl > 0.0 && opt_.cfl <= 0.9)) throw InputError("cfl", fmt::format("{:g} is out of range; valid (0, 0.9]", opt_.cfl));
  if (!(opt_.fragment_fold >= 0.0 && opt_.fragment_fold <= kAlphaMin))
    throw InputError("fragment_fold", fmt::format("{:g} is out of range; valid [0, {:g}]", opt_.fragment_fold, kAlphaMin));
  if (!opt_.inflow_barred.empty()) {
    const int M = static_cast<int>(mats_.size());
    if (opt_.inflow_fill < 0 || opt_.inflow_fill >= M || mats_[static_cast<std::size_t>(opt_.inflow_fill)].eos != materials::EosKind::IdealGas)
      throw InputError("inflow_fill", fmt::format("material {} must be an ideal gas of the {}", opt_.inflow_fill, M));
    if (!(opt_.inflow_fill_rho > 0.0 && opt_.inflow_fill_p > 0.0 && std::isfinite(opt_.inflow_fill_rho) && std::isfinite(opt_.inflow_fill_p)))
      throw InputError("inflow_fill", "its reference density and pressure must be positive");
    for (const int k : opt_.inflow_barred)
      if (k < 0 || k >= M || k == opt_.inflow_fill) throw InputError("inflow_barred", fmt::format("material {} is not one of the {} other than the fill", k, M));
  }
  if (grid_.curvilinear() && opt_.boundary[0][0] != BoundaryKind::Reflect && grid_.axis(0).lo() == 0.0)
    throw InputError("boundary.r_min", "the axis r = 0 must be a symmetry (reflect) boundary");
  const std::size_t total = grid_.totalCells();
  fields_.resize(mats_.size());
  for (std::size_t k = 0; k < mats_.size(); ++k) {
    auto& f = fields_[k];
    f.alpha.assign(total, 0.0);
    f.rho.assign(total, mats_[k].referenceDensity());
    f.e.assign(total, 0.0);
    f.h0.assign(total, 0.0);
    if (mats_[k].hasStrength())
      for (auto& c : f.s) c.assign(total, 0.0);
  }
  for (auto& c : u_) c.assign(total, 0.0);
  if (mats_.size() > 1) wlic_.assign(total * mats_.size(), 1.0);
  light_distance_.assign(total, std::numeric_limits<double>::infinity());
  light_delay_.assign(total, 0.0);
  burn_length_.assign(total, 0.0);
  for (std::size_t c = 0; c < total; ++c) {
    const auto ix = grid_.unflatten(c);
    const Vec3 x{grid_.centre(0, ix.i), grid_.centre(1, ix.j), grid_.centre(2, ix.k)};
    double wmax = 0.0;
    for (int d = 0; d < grid_.dims(); ++d) wmax = std::max(wmax, grid_.width(d, d == 0 ? ix.i : (d == 1 ? ix.j : ix.k)));
    burn_length_[c] = wmax;
    for (const auto& det : opt_.detonation) {
      double r2 = 0.0;
      for (int d = 0; d < grid_.dims(); ++d) r2 += (x[static_cast<std::size_t>(d)] - det.position[static_cast<std::size_t>(d)]) * (x[static_cast<std::size_t>(d)] - det.position[static_cast<std::size_t>(d)]);
      const double dist = std::sqrt(r2);
      if (dist < light_distance_[c]) {
        light_distance_[c] = dist;
        light_delay_[c] = det.time;
      }
    }
  }
}

// ------------------------------------------------------------------------------------------------
// Set-up

void Solver::paint(int mat, const std::function<bool(const Vec3&)>& inside, double rho, double e, Vec3 u, int sub, Over over) {
  if (mat < 0 || mat >= materialCount()) throw InputError("material", fmt::format("index {} out of range", mat));
  if (!(rho > 0.0) || !std::isfinite(rho))
    throw InputError(fmt::format("material.{}.density", mats_[static_cast<std::size_t>(mat)].name), fmt::format("{:g} kg/m3 must be > 0", rho));
  const int dims = grid_.dims();
  const int s1 = std::max(1, sub), s2 = dims >= 2 ? s1 : 1, s3 = dims >= 3 ? s1 : 1;
  auto& F = fields_[static_cast<std::size_t>(mat)];
  for (int i = 0; i < grid_.cells(0); ++i)
    for (int j = 0; j < grid_.cells(1); ++j)
      for (int k = 0; k < grid_.cells(2); ++k) {
        double in = 0.0, all = 0.0;
        for (int a = 0; a < s1; ++a)
          for (int b = 0; b < s2; ++b)
            for (int c = 0; c < s3; ++c) {
              const Vec3 x{grid_.face(0, i) + (a + 0.5) / s1 * grid_.width(0, i),
                           dims >= 2 ? grid_.face(1, j) + (b + 0.5) / s2 * grid_.width(1, j) : 0.0,
                           dims >= 3 ? grid_.face(2, k) + (c + 0.5) / s3 * grid_.width(2, k) : 0.0};
              const double wgt = grid_.axisymmetric() ? x[0] : (grid_.spherical() ? x[0] * x[0] : 1.0);
              all += wgt;
              if (inside(x)) in += wgt;
            }
        const double f = all > 0.0 ? in / all : 0.0;
        if (f <= 0.0) continue;
        const std::size_t cell = grid_.index(i, j, k);
        auto& background = fields_[0].alpha[cell];
        double added = f;
        // Disjoint regions' shares of a cell, each a quotient, may sum an ulp or so past one: the
        // background left is then all taken.
        if (over == Over::background && mat != 0 && f <= background + 1e-12) {
          added = std::min(f, background);
          background -= added;   // where the cell held the background alone, the same bits as in proportion
          if (background == 0.0) fields_[0].clearCell(cell);
        } else {
          for (std::size_t q = 0; q < fields_.size(); ++q) {
            fields_[q].alpha[cell] *= (1.0 - f);
            // a material painted over is cleared, as the sweep clears one that leaves a cell: where
            // a material's fraction is zero, so are its energy, history and stress
            if (fields_[q].alpha[cell] == 0.0 && q != static_cast<std::size_t>(mat)) fields_[q].clearCell(cell);
          }
        }
        F.alpha[cell] += added;
        F.rho[cell] = rho;
        F.e[cell] = e;
        F.h0[cell] = 0.0;
        for (int d = 0; d < 3; ++d) u_[static_cast<std::size_t>(d)][cell] = (1.0 - f) * u_[static_cast<std::size_t>(d)][cell] + f * u[static_cast<std::size_t>(d)];
      }
}

void Solver::setVelocity(std::size_t cell, Vec3 u) {
  for (int d = 0; d < 3; ++d) u_[static_cast<std::size_t>(d)][cell] = u[static_cast<std::size_t>(d)];
}

void Solver::setSpecificEnergy(int mat, std::size_t cell, double e) { fields_[static_cast<std::size_t>(mat)].e[cell] = e; }

void Solver::setBody(const std::function<bool(const Vec3&)>& inside) {
  body_.assign(grid_.totalCells(), 0);
  for (std::size_t c = 0; c < body_.size(); ++c) {
    const auto ix = grid_.unflatten(c);
    Vec3 x{grid_.centre(0, ix.i), grid_.centre(1, ix.j), grid_.centre(2, ix.k)};
    if (grid_.curvilinear()) x[0] = std::abs(x[0]);   // the axis (centre) ghosts mirror the body
    body_[c] = inside(x) ? 1 : 0;
  }
  body_impulse_mat_.assign(mats_.size(), Vec3{});
  for (auto& v : body_impulse_near_) v.assign(mats_.size(), Vec3{});
}

void Solver::moveMeshWithBody(int axis, double anchor_below, double anchor_above) {
  if (body_.empty()) throw InputError("target", "the mesh moves with a body: set the body first");
  if (axis < 0 || axis >= grid_.dims() || (axis == 0 && grid_.curvilinear()))
    throw InputError("target", "the body moves the mesh along z (axisymmetric) or any Cartesian axis");
  if (axis == 0 && grid_.isSlab()) throw InputError("target", "a domain split along axis 0 cannot move its mesh along it");
  mesh_axis_ = axis;
  anchor_below_ = anchor_below;
  anchor_above_ = anchor_above;
  body_offset_ = 0.0;
  faces0_ = grid_.axis(axis).faces();   // the mesh at offset 0 (a slab cut later keeps it)
  bandMovingMesh();
}

// The body's band of faces along the moving axis (over the whole domain: a slab without the body
// moves its mesh as the whole does), and the fixed faces nearest the anchors.
void Solver::bandMovingMesh() {
  const int axis = mesh_axis_;
  int lo = grid_.cells(axis), hi = -1;
  for (std::size_t c = 0; c < body_.size(); ++c) {
    if (!body_[c] || !grid_.isInterior(c)) continue;
    const auto ix = grid_.unflatten(c);
    const int j = axis == 0 ? ix.i : (axis == 1 ? ix.j : ix.k);
    lo = std::min(lo, j);
    hi = std::max(hi, j + 1);
  }
  if (exchange_ && exchange_->size() > 1) {
    lo = static_cast<int>(exchange_->minimum(lo));
    hi = -static_cast<int>(exchange_->minimum(-hi));
  } else if (grid_.isSlab()) {
    return;   // completed by setExchange, which sees the other slabs
  }
  if (hi < 0) throw InputError("target", "the body holds no cell of the mesh");
  const auto& f = faces0_;
  auto nearest = [&](double z) {
    int best = 0;
    for (int q = 0; q < static_cast<int>(f.size()); ++q)
      if (std::abs(f[static_cast<std::size_t>(q)] - z) < std::abs(f[static_cast<std::size_t>(best)] - z)) best = q;
    return best;
  };
  const int below = std::min(nearest(anchor_below_), lo - 1), above = std::max(nearest(anchor_above_), hi + 1);
  if (below < 0 || above > grid_.cells(axis))
    throw InputError("target", "the body needs at least one cell of mesh below and above it to move through");
  f_lo_ = below;
  f_b0_ = lo;
  f_b1_ = hi;
  f_hi_ = above;
}

mesh::Axis Solver::movedAxis(double offset) const {
  std::vector<double> f = faces0_;
  const auto at = [&](int q) { return faces0_[static_cast<std::size_t>(q)]; };
  const double zlo = at(f_lo_), zb0 = at(f_b0_), zb1 = at(f_b1_), zhi = at(f_hi_);
  for (int q = f_lo_ + 1; q < f_hi_; ++q) {
    const double z0 = at(q);
    double w = 1.0;   // the body's band moves rigidly; below and above it the mesh stretches or closes up
    if (q < f_b0_) w = (z0 - zlo) / (zb0 - zlo);
    else if (q > f_b1_) w = (zhi - z0) / (zhi - zb1);
    f[static_cast<std::size_t>(q)] = z0 + w * offset;
  }
  // A cell squeezed to a quarter of its height (or stretched fourfold) would cost the run its time
  // step or its resolution: the body has left the room the deck gave it.
  for (std::size_t q = 0; q + 1 < f.size(); ++q) {
    const double ratio = (f[q + 1] - f[q]) / (faces0_[q + 1] - faces0_[q]);
    if (!(ratio > 0.25 && ratio < 4.0))
      throw RunError(fmt::format("the body has moved {:.4g} m along axis {} at t = {:.6g} s: the mesh between it and z = {:.4g} m or {:.4g} m "
                                 "cannot stretch further (raise the domain, or end the run sooner)",
                                 offset, mesh_axis_, time_, zlo, zhi));
  }
  return mesh::Axis(std::move(f));
}

namespace {
constexpr std::uint64_t kCheckpointMagic = 0x454a45435441434bULL;   // "EJECTACK"
template <class T>
void putRaw(std::ostream& os, const T& v) { os.write(reinterpret_cast<const char*>(&v), sizeof(T)); }
template <class T>
void getRaw(std::istream& is, T& v) { is.read(reinterpret_cast<char*>(&v), sizeof(T)); }
void putVec(std::ostream& os, const std::vector<double>& v) {
  putRaw(os, static_cast<std::uint64_t>(v.size()));
  os.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(double)));
}
void getVec(std::istream& is, std::vector<double>& v) {
  std::uint64_t n = 0;
  getRaw(is, n);
  if (!is || n != v.size()) throw InputError("restart", "the checkpoint does not match this deck's mesh and materials");
  is.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(n * sizeof(double)));
}
}  // namespace

void Solver::writeCheckpoint(std::ostream& os) const {
  putRaw(os, kCheckpointMagic);
  putRaw(os, static_cast<std::uint64_t>(grid_.totalCells()));
  putRaw(os, static_cast<std::uint64_t>(mats_.size()));
  putRaw(os, time_);
  putRaw(os, last_dt_);
  putRaw(os, step_);
  putRaw(os, stats_.cell_updates);
  putRaw(os, body_velocity_);
  for (const auto& f : fields_) {
    for (const auto* v : {&f.alpha, &f.rho, &f.e, &f.h0}) putVec(os, *v);
    if (!f.s[0].empty())
      for (const auto& c : f.s) putVec(os, c);
  }
  for (const auto& c : u_) putVec(os, c);
  putRaw(os, energy_);
  putRaw(os, body_offset_);
  putRaw(os, dt_free_);
}

void Solver::readCheckpoint(std::istream& is) {
  std::uint64_t magic = 0, cells = 0, nm = 0;
  getRaw(is, magic);
  getRaw(is, cells);
  getRaw(is, nm);
  if (!is || magic != kCheckpointMagic) throw InputError("restart", "not an ejecta checkpoint");
  if (cells != grid_.totalCells() || nm != mats_.size())
    throw InputError("restart", "the checkpoint does not match this deck's mesh and materials");
  getRaw(is, time_);
  getRaw(is, last_dt_);
  getRaw(is, step_);
  getRaw(is, stats_.cell_updates);
  getRaw(is, body_velocity_);
  stats_.steps = step_;
  for (auto& f : fields_) {
    for (auto* v : {&f.alpha, &f.rho, &f.e, &f.h0}) getVec(is, *v);
    if (!f.s[0].empty())
      for (auto& c : f.s) getVec(is, c);
  }
  for (auto& c : u_) getVec(is, c);
  getRaw(is, energy_);
  getRaw(is, body_offset_);
  getRaw(is, dt_free_);
  if (!is) throw InputError("restart", "the checkpoint is truncated");
  if (!(dt_free_ >= 0.0 && std::isfinite(dt_free_))) throw InputError("restart", "the checkpoint is damaged (time step)");
  if (!std::isfinite(body_offset_) || (mesh_axis_ < 0 && body_offset_ != 0.0))
    throw InputError("restart", "the checkpoint's body offset does not fit this set-up");
  // A run only checkpoints an offset its mesh took: one the mesh cannot take is a damaged
  // checkpoint (exit 2), not a blow-up (movedAxis's RunError, exit 3).
  if (mesh_axis_ >= 0) {
    try {
      grid_.moveFaces(mesh_axis_, movedAxis(body_offset_));
    } catch (const RunError&) {
      throw InputError("restart", "the checkpoint's body offset does not fit this set-up");
    }
  }
}

// ------------------------------------------------------------------------------------------------
// State queries

double Solver::density(std::size_t cell) const {
  double rho = 0.0;
  for (const auto& f : fields_) rho += f.alpha[cell] * f.rho[cell];
  return rho;
}

double Solver::materialPressure(int mat, std::size_t cell) const {
  const auto& f = fields_[static_cast<std::size_t>(mat)];
  if (f.alpha[cell] <= 0.0) return 0.0;
  return materials::evaluateEos(mats_[static_cast<std::size_t>(mat)], f.rho[cell], f.e[cell], f.h0[cell]).pressure;
}

double Solver::pressure(std::size_t cell) const {
  double p = 0.0;
  for (int k = 0; k < materialCount(); ++k) p += fields_[static_cast<std::size_t>(k)].alpha[cell] * materialPressure(k, cell);
  return p;
}

// Per column of axis 0, in order: each material's mass, internal and kinetic energy, then the
// momentum (3). Summed column after column (totalsOf), the whole's totals are the same numbers
// whether its columns were summed in one process or gathered from its slabs.
std::vector<double> Solver::columnTotals() const {
  const std::size_t M = fields_.size(), R = 3 * M + 3;
  std::vector<double> out(R * static_cast<std::size_t>(grid_.cells(0)), 0.0);
  for (int i = 0; i < grid_.cells(0); ++i) {
    double* col = out.data() + R * static_cast<std::size_t>(i);
    for (int j = 0; j < grid_.cells(1); ++j)
      for (int k = 0; k < grid_.cells(2); ++k) {
        const std::size_t c = grid_.index(i, j, k);
        if (isBody(c)) continue;
        const double v = grid_.cellVolume(i, j, k);
        double m = 0.0;
        const double u2 = u_[0][c] * u_[0][c] + u_[1][c] * u_[1][c] + u_[2][c] * u_[2][c];
        for (std::size_t q = 0; q < M; ++q) {
          const double mq = fields_[q].alpha[c] * fields_[q].rho[c] * v;
          col[q] += mq;
          col[M + q] += mq * fields_[q].e[c];
          col[2 * M + q] += 0.5 * mq * u2;
          m += mq;
        }
        for (std::size_t d = 0; d < 3; ++d) col[3 * M + d] += m * u_[d][c];
      }
  }
  return out;
}

Totals Solver::totalsOf(const std::vector<double>& columns) const {
  const std::size_t M = fields_.size(), R = 3 * M + 3;
  Totals t;
  t.mass.assign(M, 0.0);
  t.internal_by_material.assign(M, 0.0);
  t.kinetic_by_material.assign(M, 0.0);
  t.boundary_in = energy_.boundary_in;
  t.target_work = energy_.target_work;
  t.gravity_work = energy_.gravity_work;
  t.folded_mass.assign(energy_.folded_mass.begin(), energy_.folded_mass.begin() + static_cast<std::ptrdiff_t>(M));
  t.boundary_mass.assign(energy_.boundary_mass.begin(), energy_.boundary_mass.begin() + static_cast<std::ptrdiff_t>(M));
  for (std::size_t at = 0; at + R <= columns.size(); at += R) {
    for (std::size_t q = 0; q < M; ++q) {
      t.mass[q] += columns[at + q];
      t.internal_by_material[q] += columns[at + M + q];
      t.kinetic_by_material[q] += columns[at + 2 * M + q];
    }
    for (std::size_t d = 0; d < 3; ++d) t.momentum[d] += columns[at + 3 * M + d];
  }
  for (std::size_t q = 0; q < M; ++q) {
    t.internal_energy += t.internal_by_material[q];
    t.kinetic_energy += t.kinetic_by_material[q];
  }
  return t;
}

Totals Solver::totals() const { return totalsOf(columnTotals()); }

// The signal speed of one cell: the frozen mixture's, sum(alpha_k K_k) / rho_mix (Voigt; K with
// 4/3 G for a material with strength), which is sum(Y_k c_k^2) over the mass fractions Y_k: the
// speed at which a wave crosses the cell before its pressures relax. The faces' acoustic solve
// (impedance sqrt(rho_mix sum alpha_k K_k), bulk only) is bounded by it; the predictor's Reuss
// stiffness is never above it; the closure shares the cell's volume change by compressibility, so a
// stiff minority strains K_Reuss / K_k times as much as the cell, and no wave runs inside it.
// Revision 13: no material's own speed counts beside it (until then each one's did where it held
// 1% of the cell's mass, and a dust of sand in thin products set the V-plates' late steps at the
// sand's own 3.2 km/s; docs/solver.md, "Revision 13: the step of a mixed cell"). A material's own
// speed is at most 1/sqrt(Y_k) times the mixture's.
// With SolverOptions::mixture_reuss a mixed cell's bulk stiffness is instead the Reuss modulus
// K_R = 1 / sum(alpha_k / K_k) that the closure's sharing by compressibility answers a volume change
// with, plus the dilution stiffness D = max(0, sum alpha_k p_k - K_R sum alpha_k p_k / K_k) of a cell
// out of pressure equilibrium (the soft material takes an expansion and the stiff one's share of the
// mean pressure falls with its fraction; zero at one pressure), plus sum alpha_k 4/3 G_k (each
// material's deviator follows the cell's strain). `soft` (else 0) is then the fraction of the cell's
// volume that a compression closes: sum alpha_k w_k, w_k = (alpha_k / K_k) K_R.
struct CellSignal {
  double c2 = 0.0;          // m2/s2
  double soft = 0.0;        // -: 0 in a cell of one material or without mixture_reuss
  double frozen_c2 = 0.0;   // m2/s2: the frozen sum's, with mixture_reuss (a bound on the closing's speed)
  double rho = 0.0;         // kg/m3: the cell's mean density
  double p = 0.0;           // Pa: sum alpha_k p_k over the materials above kAlphaMin
};
static CellSignal cellSignal(const std::vector<materials::Material>& mats, const std::vector<MaterialFields>& fields, std::size_t c, bool reuss) {
  double kv = 0.0, rho_mix = 0.0, compliance = 0.0, soft_sum = 0.0, shear = 0.0, p_sum = 0.0, p_per_k = 0.0;
  int present = 0;
  for (std::size_t q = 0; q < fields.size(); ++q) {
    const auto& f = fields[q];
    rho_mix += f.alpha[c] * f.rho[c];
    if (f.alpha[c] <= kAlphaMin) continue;
    ++present;
    const auto st = materials::evaluateEos(mats[q], f.rho[c], f.e[c], f.h0[c]);
    double kk = st.bulk;
    if (reuss && kk > 0.0) {
      compliance += f.alpha[c] / kk;
      soft_sum += f.alpha[c] * f.alpha[c] / kk;
      p_per_k += f.alpha[c] * st.pressure / kk;
    }
    p_sum += f.alpha[c] * st.pressure;
    if (mats[q].hasStrength()) {
      const double g4 = 4.0 / 3.0 * materials::shearModulus(mats[q], f.h0[c], st.pressure);
      kk += g4;
      shear += f.alpha[c] * g4;
    }
    kv += f.alpha[c] * kk;
  }
  if (!reuss || present < 2 || !(compliance > 0.0)) return {kv / rho_mix, 0.0, kv / rho_mix, rho_mix, p_sum};
  const double k_r = 1.0 / compliance;
  return {(k_r + std::max(p_sum - k_r * p_per_k, 0.0) + shear) / rho_mix, soft_sum * k_r, kv / rho_mix, rho_mix, p_sum};
}

// The time one cell allows along each axis. With a soft fraction (mixture_reuss) a compression
// closes it as a snow-plough shock, whose speed over the gas-laden cell is |du| / alpha_soft: the
// rate at which the cell's faces close its volume (`closing`, m/s over the cell's width) adds that
// to the cell's signal speed, so that a sweep closes at most a Courant number's share of the soft
// volume; but never past the frozen mixture's speed, at which the stiff material's own wave
// outruns the closing (a sand cell holding a few percent of gas would otherwise take du / 0.05).
// Each face moves at the acoustic solution's velocity between the cell and its neighbour (their
// impedances and mean pressures; the body's own velocity where the neighbour is body): beside a
// stiff neighbour the face moves with it, where the mean of the two velocities halved the
// closing. Along a radius the faces' areas differ, so a converging flow closes a ring or a shell
// even at one velocity (the cell on the axis twice as fast as the plane's difference says). The
// neighbours are read as prepareStepNeighbours left their ghosts.
double Solver::cellStepTime(int i, int j, int k) const {
  const std::size_t c = grid_.index(i, j, k);
  double least = std::numeric_limits<double>::infinity();
  if (isBody(c)) return least;
  const auto sig = cellSignal(mats_, fields_, c, opt_.mixture_reuss);
  const double cs = std::sqrt(sig.c2);
  const int idx[3] = {i, j, k};
  for (int d = 0; d < grid_.dims(); ++d) {
    const auto& ud = u_[static_cast<std::size_t>(d)];
    double signal = cs;
    if (sig.soft > 0.0) {
      const std::size_t st = static_cast<std::size_t>(grid_.stride(d));
      const double body_u = body_velocity_[static_cast<std::size_t>(d)];
      // the acoustic face velocity between cells l and r: (Z_l u_l + Z_r u_r + p_l - p_r) / (Z_l + Z_r),
      // each side's impedance rho c and mean pressure from its own signal (a mixed cell's neighbours
      // only: most cells have no soft fraction and read none)
      const auto side = [&](std::size_t n) {
        const auto sn = n == c ? sig : cellSignal(mats_, fields_, n, true);
        return std::pair{sn.rho * std::sqrt(std::max(sn.c2, 0.0)), sn.p};
      };
      auto face = [&](std::size_t l, std::size_t r) {
        const auto [zl, pl] = side(l);
        const auto [zr, pr] = side(r);
        const double zs = zl + zr;
        return zs > 0.0 ? (zl * ud[l] + zr * ud[r] + pl - pr) / zs : 0.5 * (ud[l] + ud[r]);
      };
      const double lo = isBody(c - st) ? body_u : face(c - st, c), hi = isBody(c + st) ? body_u : face(c, c + st);
      double closing = lo - hi;
      if (d == 0 && grid_.curvilinear()) {   // the faces' areas over the cell's volume, times its width
        const double w_per_v = grid_.width(0, i) / grid_.cellVolume(i, j, k);
        closing = grid_.faceArea(0, i, j, k) * w_per_v * lo - grid_.faceArea(0, i + 1, j, k) * w_per_v * hi;
      }
      signal = std::max(cs, std::min(cs + std::max(closing, 0.0) / sig.soft, std::sqrt(sig.frozen_c2)));
    }
    const double t = grid_.width(d, idx[d]) / (std::abs(ud[c]) + signal + 1e-30);
    least = t < least ? t : least;
  }
  return least;
}

double Solver::stableTimeStep() {
  prepareStepNeighbours();
  double dt = parallel::minOverCells(grid_.cells(0), grid_.cells(1), grid_.cells(2), useThreads(), step_balance_,
                                     [this](int i, int j, int k) { return cellStepTime(i, j, k); });
  if (exchange_) dt = exchange_->minimum(dt);
  return opt_.cfl * dt;
}

// What the step reads beyond each cell (mixture_reuss only): the neighbouring slabs' and the
// boundaries' ghosts as they are now, so that a slab's step is the whole's (a mixed cell's faces
// take their neighbours' velocities and signals).
void Solver::prepareStepNeighbours() {
  if (!opt_.mixture_reuss) return;
  if (exchange_) exchangeHalo(false);
  for (int d = 0; d < grid_.dims(); ++d) fillGhosts(d, GhostFill::StatesAndVelocity);
}

std::string Solver::describeLimitingCell() const {
  double best = std::numeric_limits<double>::infinity();
  std::size_t cell = 0;
  for (int i = 0; i < grid_.cells(0); ++i)
    for (int j = 0; j < grid_.cells(1); ++j)
      for (int k = 0; k < grid_.cells(2); ++k) {
        const double t = cellStepTime(i, j, k);
        if (t < best) {
          best = t;
          cell = grid_.index(i, j, k);
        }
      }
  const auto ix = grid_.unflatten(cell);
  std::string s = fmt::format("limited by cell ({}, {}, {}) at x = ({:.4g}, {:.4g}, {:.4g}) m, velocity ({:.4g}, {:.4g}, {:.4g}) m/s:", ix.i + grid_.offset0(), ix.j, ix.k,
                              grid_.centre(0, ix.i), grid_.centre(1, ix.j), grid_.centre(2, ix.k), u_[0][cell], u_[1][cell], u_[2][cell]);
  for (std::size_t q = 0; q < mats_.size(); ++q) {
    const auto& f = fields_[q];
    if (f.alpha[cell] <= 0.0) continue;
    const auto st = materials::evaluateEos(mats_[q], f.rho[cell], f.e[cell], f.h0[cell]);
    s += fmt::format(" [{} alpha {:.3g}, rho {:.4g} kg/m3, e {:.3g} J/kg, p {:.3g} Pa, c {:.3g} m/s]", mats_[q].name, f.alpha[cell], f.rho[cell],
                     f.e[cell], st.pressure, std::sqrt(st.bulk / f.rho[cell]));
  }
  return s;
}

// ------------------------------------------------------------------------------------------------
// Boundaries: fill the ghost layers normal to axis d.

void Solver::fillGhosts(int d, GhostFill what) {
  if (d >= grid_.dims()) return;
  const int n = grid_.cells(d);
  // The plane's two transverse axes, the one with the smaller stride inside (axis 2 is contiguous):
  // a plane normal to axis 1 walked with axis 0 inside strides over whole slabs per cell.
  const int t_out = std::min((d + 1) % 3, (d + 2) % 3), t_in = std::max((d + 1) % 3, (d + 2) % 3);
  const int lo_out = -grid_.ghost(t_out), hi_out = grid_.cells(t_out) + grid_.ghost(t_out);
  const int lo_in = -grid_.ghost(t_in), hi_in = grid_.cells(t_in) + grid_.ghost(t_in);
  auto at = [&](int along, int a, int b) {
    int idx[3];
    idx[d] = along;
    idx[t_out] = a;
    idx[t_in] = b;
    return grid_.index(idx[0], idx[1], idx[2]);
  };
  for (int side = 0; side < 2; ++side) {
    if (d == 0 && (side == 0 ? halo_lo_ : halo_hi_)) continue;   // the neighbouring slab's cells (exchangeHalo)
    const BoundaryKind kind = opt_.boundary[static_cast<std::size_t>(d)][static_cast<std::size_t>(side)];
    auto& dst = ghost_dst_[static_cast<std::size_t>(d)][static_cast<std::size_t>(side)];
    auto& src = ghost_src_[static_cast<std::size_t>(d)][static_cast<std::size_t>(side)];
    if (dst.empty()) {
      for (int a = lo_out; a < hi_out; ++a)
        for (int b = lo_in; b < hi_in; ++b)
          for (int q = 0; q < kGhost; ++q) {
            const int ghost = side == 0 ? -1 - q : n + q;
            int from = 0;
            switch (kind) {
              case BoundaryKind::Reflect: from = side == 0 ? q : n - 1 - q; break;
              case BoundaryKind::Transmit: from = side == 0 ? 0 : n - 1; break;
              case BoundaryKind::Periodic: from = side == 0 ? n - 1 - q : q; break;
            }
            dst.push_back(at(ghost, a, b));
            src.push_back(at(std::clamp(from, 0, n - 1), a, b));
          }
    }
    // the arrays to copy and their signs, then the copies in blocks of the list on the threads: no
    // ghost of axis d is a source (from lies in 0 .. n - 1) and no ghost is listed twice, so the
    // blocks neither race nor depend on their order
    std::array<std::pair<double*, double>, 3 + kMaxMaterials * 10> arrays{};
    std::size_t count = 0;
    auto add = [&](std::vector<double>& v, double sign) { arrays[count++] = {v.data(), sign}; };
    const std::size_t cells = dst.size();
    const bool barring = kind == BoundaryKind::Transmit && !opt_.inflow_barred.empty();
    // A fill without the stresses leaves their ghosts as they were: no kernel reads them before
    // the sweep along d fills them again (its gather reads ghosts along d only).
    const bool stresses = what == GhostFill::Everything;
    for (auto& f : fields_) {
      // A material absent from the boundary's cells and from its ghosts has nothing to copy: its
      // ghosts' fraction is already zero, and no kernel reads a material's state where it is zero.
      bool in_cells = false, in_ghosts = false;
      for (std::size_t i = 0; i < cells && !in_cells; ++i) in_cells = f.alpha[src[i]] != 0.0;
      for (std::size_t i = 0; i < cells && !in_cells && !in_ghosts; ++i) in_ghosts = f.alpha[dst[i]] != 0.0;
      if (!in_cells && !in_ghosts) continue;
      // One that has left the boundary's cells entirely is copied whole, whatever the fill: its
      // ghosts are cleared as its cells are, and no fill after copies it again.
      const bool whole = !in_cells;
      add(f.alpha, 1.0);
      add(f.rho, 1.0);
      add(f.e, 1.0);
      add(f.h0, 1.0);
      if (f.s[0].empty() || (!stresses && !whole)) continue;
      for (int c = 0; c < 6; ++c) {
        // a mirror flips the shear stresses across it
        const bool flip = kind == BoundaryKind::Reflect && c >= 3 && (c == stressIndex(d, (d + 1) % 3) || c == stressIndex(d, (d + 2) % 3));
        add(f.s[static_cast<std::size_t>(c)], flip ? -1.0 : 1.0);
      }
    }
    for (std::size_t c = 0; c < 3; ++c) add(u_[c], kind == BoundaryKind::Reflect && static_cast<int>(c) == d ? -1.0 : 1.0);
    constexpr std::size_t kBlock = 1024;
    parallel::forEachBlock((cells + kBlock - 1) / kBlock, useThreads(), ghost_balance_[static_cast<std::size_t>(d)][static_cast<std::size_t>(side)], [&](std::size_t blk) {
      const std::size_t first = blk * kBlock, last = std::min(cells, first + kBlock);
      for (std::size_t k = 0; k < count; ++k) {
        double* const v = arrays[k].first;
        const double sign = arrays[k].second;
        for (std::size_t i = first; i < last; ++i) v[dst[i]] = sign * v[src[i]];
      }
    });
    if (barring) barInflow(d, side, dst, src);
  }
}

// Where the flow enters through an outflow boundary, the barred materials' share of each ghost cell
// becomes the fill gas at their pressure (SolverOptions::inflow_barred). `ghosts` and `sources`:
// this side's ghost cells and the boundary cells they copied (fillGhosts).
void Solver::barInflow(int d, int side, const std::vector<std::size_t>& ghosts, const std::vector<std::size_t>& sources) {
  const auto& gas = mats_[static_cast<std::size_t>(opt_.inflow_fill)];
  const double gamma = gas.gas.gamma, p_ref = opt_.inflow_fill_p, rho_ref = opt_.inflow_fill_rho;
  auto& A = fields_[static_cast<std::size_t>(opt_.inflow_fill)];
  const auto& un = u_[static_cast<std::size_t>(d)];
  for (std::size_t i = 0; i < ghosts.size(); ++i) {
    // the boundary cell's velocity, not the face's: where the two differ in sign a sliver can enter
    const double u_in = side == 0 ? un[sources[i]] : -un[sources[i]];
    if (!(u_in > 0.0)) continue;   // leaving or at rest: the copy stands
    const std::size_t g = ghosts[i];
    for (const int k : opt_.inflow_barred) {
      auto& F = fields_[static_cast<std::size_t>(k)];
      const double v = F.alpha[g];
      if (!(v > 0.0)) continue;
      // a floor of a thousandth of the reference pressure keeps the gas's density positive where
      // the products have expanded to almost nothing
      const double p = std::max(materials::evaluateEos(mats_[static_cast<std::size_t>(k)], F.rho[g], F.e[g], F.h0[g]).pressure, 1e-3 * p_ref);
      const double rho = rho_ref * std::pow(p / p_ref, 1.0 / gamma), e = p / ((gamma - 1.0) * rho);
      // mixed by mass with the gas the ghost holds already (none: its stale state is not read)
      const bool held = A.alpha[g] > 0.0;
      const double m_old = held ? A.alpha[g] * A.rho[g] : 0.0, m_new = v * rho;
      A.e[g] = ((held ? m_old * A.e[g] : 0.0) + m_new * e) / (m_old + m_new);
      A.alpha[g] = (held ? A.alpha[g] : 0.0) + v;
      A.rho[g] = (m_old + m_new) / A.alpha[g];
      F.clearCell(g);
    }
  }
}

// ------------------------------------------------------------------------------------------------
// A slab of a decomposed domain: its neighbours' cells in its ghost layers along axis 0, and the
// body's load in the whole's order.

void Solver::setExchange(parallel::Exchange* ex) {
  exchange_ = ex;
  halo_lo_ = halo_hi_ = false;
  if (!ex || ex->size() == 1) return;
  if (mesh_axis_ == 0) throw InputError("mesh", "a domain split along axis 0 cannot move its mesh along it");
  if (opt_.boundary[0][0] == BoundaryKind::Periodic || opt_.boundary[0][1] == BoundaryKind::Periodic)
    throw InputError("mesh", "a domain split along axis 0 cannot be periodic along it");
  if (grid_.cells(0) < kGhost) throw InputError("mesh", fmt::format("a slab needs at least {} cells along axis 0", kGhost));
  halo_lo_ = grid_.offset0() > 0;
  halo_hi_ = grid_.offset0() + grid_.cells(0) < grid_.globalCells0();
  if (mesh_axis_ >= 0) bandMovingMesh();   // the body's band over the whole domain
}

Solver Solver::slab(int begin, int end) const {
  if (grid_.isSlab()) throw InputError("mesh", "a slab is cut from the whole solver");
  Solver s(*this);
  s.grid_ = grid_.slab(begin, end);
  s.exchange_ = nullptr;
  s.halo_lo_ = s.halo_hi_ = false;
  // the whole's ghost lists do not index the slab's cells: fillGhosts builds the slab's own
  for (auto* lists : {&s.ghost_dst_, &s.ghost_src_})
    for (auto& axis : *lists)
      for (auto& side : axis) side.clear();
  const std::size_t total = s.grid_.totalCells(), whole_total = grid_.totalCells();
  std::vector<std::size_t> from(total);   // each slab cell's cell in the whole
  for (std::size_t c = 0; c < total; ++c) {
    const auto ix = s.grid_.unflatten(c);
    from[c] = grid_.index(ix.i + begin, ix.j, ix.k);
  }
  auto cut = [&](const std::vector<double>& w) {
    std::vector<double> v(total);
    for (std::size_t c = 0; c < total; ++c) v[c] = w[from[c]];
    return v;
  };
  for (std::size_t k = 0; k < fields_.size(); ++k) {
    auto& f = s.fields_[k];
    const auto& w = fields_[k];
    f.alpha = cut(w.alpha);
    f.rho = cut(w.rho);
    f.e = cut(w.e);
    f.h0 = cut(w.h0);
    if (!w.s[0].empty())
      for (std::size_t q = 0; q < 6; ++q) f.s[q] = cut(w.s[q]);
  }
  for (std::size_t q = 0; q < 3; ++q) s.u_[q] = cut(u_[q]);
  if (!body_.empty()) {
    s.body_.assign(total, 0);
    for (std::size_t c = 0; c < total; ++c) s.body_[c] = body_[from[c]];
  }
  if (!wlic_.empty()) {
    s.wlic_.assign(total * mats_.size(), 1.0);
    for (std::size_t m = 0; m < mats_.size(); ++m)
      for (std::size_t c = 0; c < total; ++c) s.wlic_[m * total + c] = wlic_[m * whole_total + from[c]];
  }
  s.light_distance_ = cut(light_distance_);
  s.light_delay_ = cut(light_delay_);
  s.burn_length_ = cut(burn_length_);
  if (begin > 0) s.energy_ = EnergyLedger{};
  return s;
}

// One cell's state as a slab sends it: the velocity, then each material's fraction, density,
// energy, history (and stress, with strength). The halo swap and the assembly share the order.
void Solver::packCell(std::size_t c, std::vector<double>& out) const {
  for (std::size_t q = 0; q < 3; ++q) out.push_back(u_[q][c]);
  for (const auto& f : fields_) {
    out.insert(out.end(), {f.alpha[c], f.rho[c], f.e[c], f.h0[c]});
    if (!f.s[0].empty())
      for (const auto& sc : f.s) out.push_back(sc[c]);
  }
}

std::size_t Solver::unpackCell(std::size_t c, const std::vector<double>& in, std::size_t at) {
  for (std::size_t q = 0; q < 3; ++q) u_[q][c] = in.at(at++);
  for (auto& f : fields_) {
    f.alpha[c] = in.at(at++);
    f.rho[c] = in.at(at++);
    f.e[c] = in.at(at++);
    f.h0[c] = in.at(at++);
    if (!f.s[0].empty())
      for (auto& sc : f.s) sc[c] = in.at(at++);
  }
  return at;
}

std::vector<double> Solver::packForAssembly(const Solver& mine) {
  const auto& g = mine.grid_;
  const int g0 = kGhost;
  // this slab's columns of axis 0 (with the domain's own ghost columns at its ends), transverse ghosts
  // included, so that the whole's ghosts are what one process would hold
  const int i_lo = g.offset0() == 0 ? -g0 : 0, i_hi = g.offset0() + g.cells(0) == g.globalCells0() ? g.cells(0) + g0 : g.cells(0);
  const int j_lo = -g.ghost(1), j_hi = g.cells(1) + g.ghost(1), k_lo = -g.ghost(2), k_hi = g.cells(2) + g.ghost(2);
  // [first column, last column + 1 (whole's indices), the ledger (3), cell updates, folded and boundary mass by material] then each cell
  // in (i, j, k) order (packCell)
  std::vector<double> out{static_cast<double>(g.offset0() + i_lo), static_cast<double>(g.offset0() + i_hi), mine.energy_.boundary_in,
                          mine.energy_.target_work, mine.energy_.gravity_work, mine.stats_.cell_updates};
  const std::size_t nm = mine.mats_.size();
  out.insert(out.end(), mine.energy_.folded_mass.begin(), mine.energy_.folded_mass.begin() + static_cast<std::ptrdiff_t>(nm));
  out.insert(out.end(), mine.energy_.boundary_mass.begin(), mine.energy_.boundary_mass.begin() + static_cast<std::ptrdiff_t>(nm));
  for (int i = i_lo; i < i_hi; ++i)
    for (int j = j_lo; j < j_hi; ++j)
      for (int k = k_lo; k < k_hi; ++k) mine.packCell(g.index(i, j, k), out);
  return out;
}

void Solver::sendForAssembly(const Solver& mine, parallel::Exchange& ex) {
  ex.gatherToFirstEach(packForAssembly(mine), [](const std::vector<double>&) {});
}

void Solver::assemble(const Solver& mine, parallel::Exchange& ex) {
  if (ex.rank() != 0 || grid_.isSlab()) throw RunError("the slabs are assembled into a whole solver on rank 0");
  const auto& g = mine.grid_;
  const int j_lo = -g.ghost(1), j_hi = g.cells(1) + g.ghost(1), k_lo = -g.ghost(2), k_hi = g.cells(2) + g.ghost(2);
  const std::size_t nm = mats_.size();
  energy_ = EnergyLedger{};
  double updates = 0.0;
  // each slab as it arrives, in rank order (the books summed in that order)
  ex.gatherToFirstEach(packForAssembly(mine), [&](const std::vector<double>& part) {
    const int first = static_cast<int>(part.at(0)), last = static_cast<int>(part.at(1));
    energy_.boundary_in += part.at(2);
    energy_.target_work += part.at(3);
    energy_.gravity_work += part.at(4);
    updates += part.at(5);
    for (std::size_t k = 0; k < nm; ++k) {
      energy_.folded_mass[k] += part.at(6 + k);
      energy_.boundary_mass[k] += part.at(6 + nm + k);
    }
    std::size_t at = 6 + 2 * nm;
    for (int i = first; i < last; ++i)
      for (int j = j_lo; j < j_hi; ++j)
        for (int k = k_lo; k < k_hi; ++k) at = unpackCell(grid_.index(i, j, k), part, at);
  });
  // the clock, the controller, the body and its mesh: the same on every slab
  time_ = mine.time_;
  last_dt_ = mine.last_dt_;
  dt_free_ = mine.dt_free_;
  step_ = mine.step_;
  stats_ = mine.stats_;
  stats_.cell_updates = updates;   // every slab's
  body_velocity_ = mine.body_velocity_;
  if (mesh_axis_ >= 0 && body_offset_ != mine.body_offset_) {
    body_offset_ = mine.body_offset_;
    grid_.moveFaces(mesh_axis_, movedAxis(body_offset_));
  }
}

void Solver::exchangeHalo(bool weights) {
  if (!halo_lo_ && !halo_hi_) return;
  const int n = grid_.cells(0), g = kGhost;
  const int lo1 = -grid_.ghost(1), hi1 = grid_.cells(1) + grid_.ghost(1), lo2 = -grid_.ghost(2), hi2 = grid_.cells(2) + grid_.ghost(2);
  const std::size_t total = grid_.totalCells();
  const int M = materialCount();
  // every cell of `g` layers starting at column i0, transverse ghosts included, in one order
  auto each = [&](int i0, auto&& f) {
    for (int q = 0; q < g; ++q)
      for (int j = lo1; j < hi1; ++j)
        for (int k = lo2; k < hi2; ++k) f(grid_.index(i0 + q, j, k));
  };
  auto pack = [&](int i0) {
    std::vector<double> out;
    each(i0, [&](std::size_t c) {
      if (!weights) return packCell(c, out);
      for (int m = 0; m < M; ++m) out.push_back(wlic_[static_cast<std::size_t>(m) * total + c]);
    });
    return out;
  };
  auto unpack = [&](int i0, const std::vector<double>& in) {
    std::size_t at = 0;
    each(i0, [&](std::size_t c) {
      if (!weights) {
        at = unpackCell(c, in, at);
        return;
      }
      for (int m = 0; m < M; ++m) wlic_[static_cast<std::size_t>(m) * total + c] = in.at(at++);
    });
    if (at != in.size()) throw RunError("a neighbouring slab sent a halo of the wrong size");
  };
  if (weights && M < 2) return;
  std::vector<double> from_lo, from_hi;
  exchange_->swapHalo(halo_lo_ ? pack(0) : std::vector<double>{}, halo_hi_ ? pack(n - g) : std::vector<double>{}, from_lo, from_hi);
  if (halo_lo_) unpack(-g, from_lo);
  if (halo_hi_) unpack(n, from_hi);
}

void Solver::combineBodyLoad(const std::vector<double>& events) {
  const int M = materialCount(), R = bodyEventSize(M);
  const auto all = exchange_->gatherAll(events);
  const std::size_t count = all.size() / static_cast<std::size_t>(R);
  // by the pencil's place in the whole; a pencil cut by slabs keeps its slabs' order (a stable sort)
  std::vector<std::size_t> order(count);
  for (std::size_t i = 0; i < count; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return all[a * R] < all[b * R]; });
  // as the whole sums them: within a pencil in order from zero, then pencil after pencil
  std::size_t i = 0;
  while (i < count) {
    const double key = all[order[i] * R];
    double total[3] = {}, by_mat[kMaxMaterials][3] = {}, near[kNearWallDepths][kMaxMaterials][3] = {};
    for (; i < count && all[order[i] * R] == key; ++i) {
      const double* e = all.data() + order[i] * R;
      const auto comp = static_cast<std::size_t>(e[1]);
      total[comp] += e[2];
      for (int k = 0; k < M; ++k) by_mat[k][comp] += e[3 + k];
      for (int l = 0; l < kNearWallDepths; ++l)
        for (int k = 0; k < M; ++k) near[l][k][comp] += e[3 + M + l * M + k];
    }
    for (std::size_t q = 0; q < 3; ++q) {
      body_impulse_[q] += total[q];
      for (int k = 0; k < M; ++k) {
        body_impulse_mat_[static_cast<std::size_t>(k)][q] += by_mat[k][q];
        for (int l = 0; l < kNearWallDepths; ++l) body_impulse_near_[static_cast<std::size_t>(l)][static_cast<std::size_t>(k)][q] += near[l][k][q];
      }
    }
  }
}

// ------------------------------------------------------------------------------------------------
// Interface orientation for the remap (weighted line interface calculation, Yokoi 2007): in a
// sweep along d, a mixed cell's flux is the sharp THINC profile in proportion |n_d| / sum |n| of
// its interface normal n = grad(alpha), and the cell mean for the rest. Without it, a split
// sharp scheme squares off curved interfaces.

void Solver::interfaceWeights(int d) {
  const int M = materialCount();
  if (M < 2) return;
  const int dims = grid_.dims();
  const int n0 = grid_.cells(0), n1 = grid_.cells(1), n2 = grid_.cells(2);
  const std::size_t total = grid_.totalCells();
  // the central difference's 1 / (x[i+1] - x[i-1]) along each axis, once per sweep, not per cell and material
  std::array<std::vector<double>, 3> per_span;
  std::ptrdiff_t stride[3] = {};
  for (int b = 0; b < dims; ++b) {
    auto& ps = per_span[static_cast<std::size_t>(b)];
    ps.resize(static_cast<std::size_t>(grid_.cells(b)));
    for (int i = 0; i < grid_.cells(b); ++i) ps[static_cast<std::size_t>(i)] = 1.0 / (grid_.centre(b, i + 1) - grid_.centre(b, i - 1));
    stride[b] = grid_.stride(b);
  }
  parallel::forEachCell(n0, n1, n2, useThreads(), weights_balance_, [&](int i, int j, int k) {
    const std::size_t c = grid_.index(i, j, k);
    const int idx[3] = {i, j, k};
    for (int m = 0; m < M; ++m) {
      const double* al = fields_[static_cast<std::size_t>(m)].alpha.data();
      // Only a mixed cell's weight is written: where a material fills the cell its weight is 1,
      // which the gather takes without reading it, and where it is absent no kernel reads it
      // (most cells are one material's: their weights were most of this pass's stores).
      if (al[c] <= 0.0 || al[c] >= 1.0) continue;
      double nd = 0.0, nsum = 0.0;
      for (int b = 0; b < dims; ++b) {
        const double g = std::abs(al[c + static_cast<std::size_t>(stride[b])] - al[c - static_cast<std::size_t>(stride[b])]) *
                         per_span[static_cast<std::size_t>(b)][static_cast<std::size_t>(idx[b])];
        nsum += g;
        if (b == d) nd = g;
      }
      wlic_[static_cast<std::size_t>(m) * total + c] = nsum > 0.0 ? nd / nsum : 1.0;
    }
  });
  // The ghosts along d take their source cells' weights, as fillGhosts (just before) gave them their
  // fractions: a periodic end's donor must carry its image's weight, and the mixture that enters at an
  // outflow side the boundary cell's. (A mirror's |n_d| / sum |n| is its source's; a neighbouring
  // slab sends its own, exchangeHalo.)
  for (int side = 0; side < 2; ++side) {
    if (d == 0 && (side == 0 ? halo_lo_ : halo_hi_)) continue;
    const auto& dst = ghost_dst_[static_cast<std::size_t>(d)][static_cast<std::size_t>(side)];
    const auto& src = ghost_src_[static_cast<std::size_t>(d)][static_cast<std::size_t>(side)];
    for (int m = 0; m < M; ++m) {
      double* w = wlic_.data() + static_cast<std::size_t>(m) * total;
      for (std::size_t i = 0; i < dst.size(); ++i) w[dst[i]] = w[src[i]];
    }
  }
}

// ------------------------------------------------------------------------------------------------
// Programmed burn: a cell's burn fraction rises from its lighting time over `burn_width` cells.

void Solver::updateBurn(double dt) {
  const double t = time_ + dt;
  for (std::size_t k = 0; k < mats_.size(); ++k) {
    if (mats_[k].eos != EosKind::Jwl) continue;
    const auto& j = mats_[k].jwl;
    auto& f = fields_[k];
    parallel::forEachCell(grid_.cells(0), grid_.cells(1), grid_.cells(2), useThreads(), burn_balance_, [&](int i, int jj, int kk) {
      const std::size_t c = grid_.index(i, jj, kk);
      if (f.alpha[c] <= 0.0 || f.h0[c] >= 1.0) return;
      const double lit = light_delay_[c] + light_distance_[c] / j.d_cj;
      const double frac = std::clamp((t - lit) * j.d_cj / (j.burn_width * burn_length_[c]), 0.0, 1.0);
      f.h0[c] = std::max(f.h0[c], frac);
    });
  }
}

// ------------------------------------------------------------------------------------------------
// Deviatoric stress: hypoelastic with Jaumann rotation, radial return to the yield surface.

void Solver::updateStress(double dt) {
  if (!any_strength_) return;
  if (exchange_) exchangeHalo(false);
  for (int d = 0; d < grid_.dims(); ++d) fillGhosts(d, GhostFill::StatesAndVelocity);
  const int dims = grid_.dims();
  const bool axi = grid_.axisymmetric(), sph = grid_.spherical();
  parallel::forEachCell(grid_.cells(0), grid_.cells(1), grid_.cells(2), useThreads(), stress_balance_, [&](int i, int j, int k) {
    const std::size_t c = grid_.index(i, j, k);
    bool any = false;
    for (std::size_t q = 0; q < mats_.size(); ++q) any = any || (mats_[q].hasStrength() && fields_[q].alpha[c] > kAlphaMin);
    if (!any) return;
    double L[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};   // L[a][b] = du_a / dx_b
    const int idx[3] = {i, j, k};
    for (int b = 0; b < dims; ++b) {
      int lo[3] = {i, j, k}, hi[3] = {i, j, k};
      lo[b] -= 1;
      hi[b] += 1;
      const std::size_t cl = grid_.index(lo[0], lo[1], lo[2]), ch = grid_.index(hi[0], hi[1], hi[2]);
      const double dx = grid_.centre(b, idx[b] + 1) - grid_.centre(b, idx[b] - 1);
      for (std::size_t a = 0; a < 3; ++a) L[a][b] = (u_[a][ch] - u_[a][cl]) / dx;
    }
    if (axi) L[2][2] = u_[0][c] / grid_.centre(0, i);   // hoop strain rate u_r / r
    if (sph) L[1][1] = L[2][2] = u_[0][c] / grid_.centre(0, i);   // both hoop directions
    double D[3][3], W[3][3];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        D[a][b] = 0.5 * (L[a][b] + L[b][a]);
        W[a][b] = 0.5 * (L[a][b] - L[b][a]);
      }
    const double trace = (D[0][0] + D[1][1] + D[2][2]) / 3.0;
    for (std::size_t q = 0; q < mats_.size(); ++q) {
      const auto& m = mats_[q];
      auto& f = fields_[q];
      if (!m.hasStrength() || f.alpha[c] <= kAlphaMin) continue;
      const double p = materials::evaluateEos(m, f.rho[c], f.e[c], f.h0[c]).pressure;
      const double G = materials::shearModulus(m, f.h0[c], p), Y = materials::yieldStrength(m, p);
      double S[3][3];
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) S[a][b] = f.s[static_cast<std::size_t>(stressIndex(a, b))][c];
      double Sn[3][3];
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          double rot = 0.0;
          for (int e = 0; e < 3; ++e) rot += W[a][e] * S[e][b] - S[a][e] * W[e][b];
          Sn[a][b] = S[a][b] + dt * (2.0 * G * (D[a][b] - (a == b ? trace : 0.0)) + rot);
        }
      const double tr = (Sn[0][0] + Sn[1][1] + Sn[2][2]) / 3.0;   // keep it deviatoric
      for (int a = 0; a < 3; ++a) Sn[a][a] -= tr;
      double j2 = 0.0;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) j2 += 0.5 * Sn[a][b] * Sn[a][b];
      const double seq = std::sqrt(3.0 * j2);
      const double scale = seq > Y ? (Y > 0.0 ? Y / seq : 0.0) : 1.0;
      for (int a = 0; a < 3; ++a)
        for (int b = a; b < 3; ++b) f.s[static_cast<std::size_t>(stressIndex(a, b))][c] = scale * Sn[a][b];
    }
  });
}

// ------------------------------------------------------------------------------------------------
// One sweep along axis d: gather each pencil, run the kernels (pencil.hpp), scatter it back.

namespace {
// One material's share of the cells' mixture (gatherPencil): density, pressure, stiffness (the
// Voigt sum, and the Reuss sum of compliances over fractions above kAlphaMin) and tension limit by
// volume fraction, added in the materials' order (an absent one adds zeros). With Reuss (the
// mixture_reuss option) also sum alpha^2 / K (the soft fraction's) and sum alpha p / K (the
// dilution stiffness's).
template <bool Reuss>
[[gnu::noinline]] void addToMixture(std::ptrdiff_t n, double tension, const double* __restrict a, const double* __restrict r,
                                    const double* __restrict pk, const double* __restrict kk, double* __restrict rho, double* __restrict p,
                                    double* __restrict kv, double* __restrict compliance, double* __restrict soft, double* __restrict p_per_k,
                                    double* __restrict present, double* __restrict pmin) {
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const double al = a[i] > 0.0 ? a[i] : 0.0;
    rho[i] += al * r[i];
    p[i] += al * pk[i];
    kv[i] += al * kk[i];
    const bool counts = al > kAlphaMin;
    compliance[i] += counts && kk[i] > 0.0 ? al / kk[i] : 0.0;
    if constexpr (Reuss) {
      soft[i] += counts && kk[i] > 0.0 ? al * al / kk[i] : 0.0;
      p_per_k[i] += counts && kk[i] > 0.0 ? al * pk[i] / kk[i] : 0.0;
    }
    present[i] += counts ? 1.0 : 0.0;
    pmin[i] += al * tension;
  }
}
// The same for the deviatoric stress of a material with strength: the normal component along the
// sweep, the hoop (zz) and rr components, and the two shear components on the sweep's faces.
[[gnu::noinline]] void addStressToMixture(std::ptrdiff_t n, const double* __restrict a, const double* __restrict s_nn,
                                          const double* __restrict s_tt, const double* __restrict s_11, const double* __restrict s_dt1,
                                          const double* __restrict s_dt2, double* __restrict snn, double* __restrict stt,
                                          double* __restrict s11, double* __restrict sh1, double* __restrict sh2) {
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const double al = a[i] > 0.0 ? a[i] : 0.0;
    snn[i] += al * s_nn[i];
    stt[i] += al * s_tt[i];
    s11[i] += al * s_11[i];
    sh1[i] += al * s_dt1[i];
    sh2[i] += al * s_dt2[i];
  }
}
}  // namespace

void Solver::gatherPencil(Pencil& P, int d, const PencilSource& src, int a, int b, const SweepSetup& S) const {
  const int N = P.N, M = P.M;
  const std::ptrdiff_t stride = src.stride;
  const bool several = materialCount() > 1;   // the interface weights exist
  const int t1 = S.t1, t2 = S.t2;
  const int s_dt1 = stressIndex(d, t1), s_dt2 = stressIndex(d, t2);
  const bool radial = grid_.curvilinear() && d == 0, spherical = grid_.spherical();
  const bool reuss = opt_.mixture_reuss;
  // geometry: areas and volumes from the transverse measure of the pencil
  double trans = grid_.width(t1, a) * grid_.width(t2, b);
  if (grid_.axisymmetric()) {
    if (d == 0) {
      trans = grid_.width(1, a);
    } else {
      const double rl = grid_.face(0, b), rr = grid_.face(0, b + 1);   // d == 1: t2 == 0
      trans = 0.5 * (rr * rr - rl * rl);
    }
  }
  for (int i = 0; i <= N; ++i) {
    const std::size_t si = static_cast<std::size_t>(i);
    if (spherical) {   // per steradian: 1D, so no transverse measure
      const double rl = S.xf[si];
      P.area[si] = rl * rl;
      if (i < N) {
        const double rr = S.xf[si + 1];
        P.vol[si] = (rr * rr * rr - rl * rl * rl) / 3.0;
      }
    } else if (radial) {
      const double rl = S.xf[si];
      P.area[si] = std::abs(rl) * trans;
      if (i < N) {
        const double rr = S.xf[si + 1];
        P.vol[si] = 0.5 * std::abs(rr * std::abs(rr) - rl * std::abs(rl)) * trans;
      }
    } else {
      P.area[si] = trans;
      if (i < N) P.vol[si] = trans * S.width[si];
    }
  }
  P.ring_width = radial ? trans : 0.0;
  P.radial = radial;
  P.spherical = spherical;
  // State and equation of state, material by material (the kind switched on once a material), then
  // the mixture's sums in the materials' order, in loops that vectorise. An absent material
  // (fraction not above zero) adds zeros: each sum starts at +0 and never becomes -0, so adding +0
  // or -0 leaves it as it was, the same sums as skipping it. Until the last loop P.P holds the sum
  // of the pressures and P.hoop that of the zz stress.
  for (int i = 0; i < N; ++i) {
    const std::ptrdiff_t c = i * stride;
    const std::size_t si = static_cast<std::size_t>(i);
    for (std::size_t q = 0; q < 3; ++q) P.u[q][si] = src.u[q][c];
    P.solid[si] = src.solid ? src.solid[c] : 0;
    P.rho[si] = P.P[si] = P.K[si] = P.Kp[si] = P.present[si] = P.pmin[si] = P.hoop[si] = P.shear[0][si] = P.shear[1][si] = P.sum_snn[si] = P.sum_s11[si] = 0.0;
    if (reuss) P.soft[si] = P.p_per_k[si] = 0.0;   // the Reuss sums (addToMixture<true>)
  }
  for (int k = 0; k < M; ++k) {
    const auto km = static_cast<std::size_t>(P.mat[k]);
    const auto& mat = mats_[km];
    const bool strength = !fields_[km].s[0].empty();
    const double *alpha = src.alpha[km], *rho = src.rho[km], *e = src.e[km], *h0 = src.h0[km], *wl = src.wl[km];
    for (int i = 0; i < N; ++i) {
      const std::ptrdiff_t c = i * stride;
      const std::size_t ki = P.at(k, i);
      const double al = alpha[c];
      P.a[ki] = al;
      if (!(al > 0.0)) {
        // An absent material's energy, history and stress are zero (every path that empties a cell
        // clears them, MaterialFields::clearCell), so they are not read: in a sweep across the
        // contiguous axis each read is a cache line of its own, for each material in each cell
        // (the invariant is tested: Solver.PencilsCarryingOnlyTheirMaterialsGiveTheSameResultToTheBit).
        // Its interface weight multiplies a zero volume in remapFluxes, whatever it is. Nor is its
        // density read: only a sliver arriving here takes it (scatterPencil reads it then), and its
        // mass a r V is zero either way.
        P.r[ki] = P.wl[ki] = P.e[ki] = P.h[ki] = 0.0;
        if (!P.strengthless[k])
          for (std::size_t q = 0; q < 6; ++q) P.s[q][ki] = 0.0;
        continue;
      }
      P.r[ki] = rho[c];
      P.wl[ki] = several && al < 1.0 ? wl[c] : 1.0;   // (interfaceWeights: a full cell's is 1, not stored)
      P.e[ki] = e[c];
      P.h[ki] = h0[c];
      if (strength)
        for (std::size_t q = 0; q < 6; ++q) P.s[q][ki] = src.s[km][q][c];
    }
    const std::size_t k0 = P.at(k, 0);
    materials::evaluateEosAndHistory(mat, N, P.a.data() + k0, P.r.data() + k0, P.e.data() + k0, P.h.data() + k0, P.pk.data() + k0,
                                     P.kk.data() + k0);
    const auto add = reuss ? addToMixture<true> : addToMixture<false>;
    add(N, materials::tensionLimit(mat), P.a.data() + k0, P.r.data() + k0, P.pk.data() + k0, P.kk.data() + k0, P.rho.data(), P.P.data(),
        P.K.data(), P.Kp.data(), P.soft.data(), P.p_per_k.data(), P.present.data(), P.pmin.data());
    if (strength)
      addStressToMixture(N, P.a.data() + k0, P.s[static_cast<std::size_t>(d)].data() + k0, P.s[2].data() + k0, P.s[1].data() + k0,
                         P.s[static_cast<std::size_t>(s_dt1)].data() + k0, P.s[static_cast<std::size_t>(s_dt2)].data() + k0,
                         P.sum_snn.data(), P.hoop.data(), P.sum_s11.data(), P.shear[0].data(), P.shear[1].data());
  }
  for (int i = 0; i < N; ++i) {
    const std::size_t si = static_cast<std::size_t>(i);
    const double p = P.P[si], stt = P.hoop[si];
    P.P[si] = p - P.sum_snn[si];
    P.hoop[si] = p - (spherical ? 0.5 * (stt + P.sum_s11[si]) : stt);
    // Until here P.Kp holds the sum of compliances. A cell of one material (fragments aside) keeps
    // K, the same to the bit whichever materials its pencil carries.
    const bool mixed = P.present[si] > 1.0 && P.Kp[si] > 0.0;
    P.Kp[si] = mixed ? 1.0 / P.Kp[si] : P.K[si];
    if (!reuss) {
      P.Z[si] = std::sqrt(std::max(P.rho[si] * P.K[si], 1e-30));
      continue;
    }
    // mixture_reuss: the faces' impedance from the stiffness the closure answers with (cellSignal):
    // K_R plus the dilution stiffness sum alpha_k p_k - K_R sum alpha_k p_k / K_k of a cell out of
    // pressure equilibrium; compressed hard, the soft fraction closes and the impedance rises by
    // rho |du| / alpha_soft (a snow-plough shock's; solveFaces), zs = rho / alpha_soft.
    const double dilution = mixed ? std::max(p - P.Kp[si] * P.p_per_k[si], 0.0) : 0.0;
    P.Z[si] = std::sqrt(std::max(P.rho[si] * (P.Kp[si] + dilution), 1e-30));
    P.zs[si] = mixed ? P.rho[si] / std::max(P.soft[si] * P.Kp[si], 1e-3) : 0.0;   // P.soft holds sum alpha^2 / K
    // the shock impedance's ceiling: the frozen sum's, as the step's speed is capped (cellStepTime),
    // so that no face answers faster than the step allows (rho dx / Z >= dt)
    P.zmax[si] = std::max(std::sqrt(std::max(P.rho[si] * P.K[si], 1e-30)), P.Z[si]);
  }
}

// A pencil's cells read in place: the mesh's arrays from the pencil's first (ghost) cell on.
Solver::PencilSource Solver::meshSource(int d, std::size_t base) const {
  PencilSource src;
  src.stride = grid_.stride(d);
  for (std::size_t q = 0; q < 3; ++q) src.u[q] = u_[q].data() + base;
  src.solid = body_.empty() ? nullptr : body_.data() + base;
  const bool several = materialCount() > 1;
  for (std::size_t k = 0; k < fields_.size(); ++k) {
    const auto& F = fields_[k];
    src.alpha[k] = F.alpha.data() + base;
    src.rho[k] = F.rho.data() + base;
    src.e[k] = F.e.data() + base;
    src.h0[k] = F.h0.data() + base;
    src.wl[k] = several ? wlic_.data() + k * grid_.totalCells() + base : nullptr;
    if (!F.s[0].empty())
      for (std::size_t q = 0; q < 6; ++q) src.s[k][q] = F.s[q].data() + base;
  }
  return src;
}

// Copies what the gather of each of a tile's pencils reads (`bases`: their first cells) into the
// scratch, cell by cell across the pencils, so that each cache line of a strided sweep is fetched
// once for the tile rather than once for each pencil; T.sources then point the gathers at it. An
// absent material's fraction alone is copied, and a full cell's interface weight not at all: the
// gather reads nothing else of them.
void Solver::stageTile(SweepScratch& T, int d, const std::size_t* bases, int pencils, int N) const {
  const std::size_t M = static_cast<std::size_t>(materialCount());
  const std::size_t W = static_cast<std::size_t>(pencils), n = static_cast<std::size_t>(N);
  constexpr std::size_t kSlots = 11;   // by material: alpha, rho, e, h0, weight, six stresses
  const std::size_t span = W * n;
  if (T.staged.size() < (3 + kSlots * M) * span) T.staged.resize((3 + kSlots * M) * span);
  if (T.staged_solid.size() < span) T.staged_solid.resize(span);
  double* const out = T.staged.data();
  // pencil w's run of the velocity component q, or of field f (0 alpha ... 4 weight, 5 + q stress) of material k
  auto velocity = [&](std::size_t q, std::size_t w) { return out + q * span + w * n; };
  auto field = [&](std::size_t k, std::size_t f, std::size_t w) { return out + (3 + kSlots * k + f) * span + w * n; };
  T.sources.resize(W);
  for (std::size_t w = 0; w < W; ++w) T.sources[w] = meshSource(d, bases[w]);   // read from here ...
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t w = 0; w < W; ++w) {
      const PencilSource& from = T.sources[w];
      const std::ptrdiff_t c = static_cast<std::ptrdiff_t>(i) * from.stride;
      for (std::size_t q = 0; q < 3; ++q) velocity(q, w)[i] = from.u[q][c];
      if (from.solid) T.staged_solid[w * n + i] = from.solid[c];
      for (std::size_t k = 0; k < M; ++k) {
        const double al = from.alpha[k][c];
        field(k, 0, w)[i] = al;
        if (!(al > 0.0)) continue;
        field(k, 1, w)[i] = from.rho[k][c];
        field(k, 2, w)[i] = from.e[k][c];
        field(k, 3, w)[i] = from.h0[k][c];
        if (from.wl[k] && al < 1.0) field(k, 4, w)[i] = from.wl[k][c];
        if (from.s[k][0])
          for (std::size_t q = 0; q < 6; ++q) field(k, 5 + q, w)[i] = from.s[k][q][c];
      }
    }
  }
  for (std::size_t w = 0; w < W; ++w) {   // ... and the gathers read the copy
    PencilSource& src = T.sources[w];
    src.stride = 1;
    for (std::size_t q = 0; q < 3; ++q) src.u[q] = velocity(q, w);
    if (src.solid) src.solid = T.staged_solid.data() + w * n;
    for (std::size_t k = 0; k < M; ++k) {
      src.alpha[k] = field(k, 0, w);
      src.rho[k] = field(k, 1, w);
      src.e[k] = field(k, 2, w);
      src.h0[k] = field(k, 3, w);
      if (src.wl[k]) src.wl[k] = field(k, 4, w);
      if (src.s[k][0])
        for (std::size_t q = 0; q < 6; ++q) src.s[k][q] = field(k, 5 + q, w);
    }
  }
}

// The materials the pencil carries (Pencil::mat): those present in any of its cells, ghosts
// included, in the run's order. Leaving out a material that is absent from the whole pencil
// changes no number: its fraction and mass are zero in every cell, so its fluxes and shares are
// zeros that leave the kernels' sums as they were, and its other values are multiplied by them.
// The sweep leaves such a material's cells as they are, where carrying it would clear them again
// (they are cleared already where the sweep or paint emptied them).
void Solver::selectMaterials(Pencil& P, const PencilSource& src) const {
  const int M = materialCount(), N = P.N;
  const std::ptrdiff_t stride = src.stride;
  int used = 0;
  for (int k = 0; k < M; ++k) {
    bool present = M == 1 || opt_.carry_all_materials;
    const double* al = src.alpha[k];
    for (int i = 0; i < N && !present; ++i) present = al[i * stride] > 0.0;
    if (present) P.mat[used++] = k;
  }
  if (used == 0) {   // nothing anywhere (cannot happen in a filled mesh): carry every material
    for (int k = 0; k < M; ++k) P.mat[k] = k;
    used = M;
  }
  P.M = used;
  for (int k = 0; k < used; ++k) P.strengthless[k] = fields_[static_cast<std::size_t>(P.mat[k])].s[0].empty();
}

// The new Eulerian state of the pencil's interior cells. Returns the first cell that went bad
// (non-finite or non-positive), or SIZE_MAX.
std::size_t Solver::scatterPencil(const Pencil& P, int d, std::size_t base, PencilLedger& ledger) {
  const int g = kGhost, n = P.n, M = P.M;
  const std::ptrdiff_t stride = grid_.stride(d);
  std::size_t bad = std::numeric_limits<std::size_t>::max();
  for (int i = g; i < g + n; ++i) {
    const std::size_t si = static_cast<std::size_t>(i), c = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(base) + i * stride);
    if (P.solid[si]) continue;   // the body's cells keep their (unused) state
    double m = 0.0, vs = 0.0, lost = 0.0;
    double mk_new[kMaxMaterials], vk_new[kMaxMaterials], ie_new[kMaxMaterials], ke_in[kMaxMaterials];
    for (int k = 0; k < M; ++k) {
      const std::size_t ki = P.at(k, i), kf = P.atFace(k, i);
      vk_new[k] = P.vk[ki] + P.fv[kf] - P.fv[kf + 1];
      mk_new[k] = P.mk[ki] + P.fm[kf] - P.fm[kf + 1];
      ie_new[k] = P.iek[ki] + P.fe[kf] - P.fe[kf + 1];
      // each material's kinetic energy after the Lagrange phase plus what its fluxes carried
      // (a material with no mass here had none of it: the quotient's +0 without the division)
      ke_in[k] = (P.mass[si] > 0.0 && P.mk[ki] != 0.0 ? P.ke[si] * P.mk[ki] / P.mass[si] : 0.0) + P.fkek[kf] - P.fkek[kf + 1];
      if (mk_new[k] <= 0.0) {   // emptied: what energy it had left goes to the others as heat
        lost += ie_new[k] + ke_in[k];
        mk_new[k] = vk_new[k] = ie_new[k] = ke_in[k] = 0.0;
      } else if (vk_new[k] <= 0.0) {
        // a sliver: keep its mass, at the density the material had here (kept where it is absent)
        const double r_here = P.a[ki] > 0.0 ? P.r[ki] : fields_[static_cast<std::size_t>(P.mat[k])].rho[c];
        vk_new[k] = mk_new[k] / std::max(r_here, 1e-30);
      }
      m += mk_new[k];
      vs += vk_new[k];
    }
    // one division per cell and one per material, the rest products (the divider is the
    // scatter's slowest unit: up to nine quotients per material and cell took it)
    const Reciprocal per_m(m);
    double mom[3], u_new[3], u2 = 0.0;
    for (std::size_t q = 0; q < 3; ++q) {
      mom[q] = P.mom[q][si] + P.fmom[q][si] - P.fmom[q][si + 1];
      u_new[q] = per_m.of(mom[q]);
      u2 += u_new[q] * u_new[q];
    }
    // The kinetic energy the remap took from the flow is returned as heat, by material.
    double heat = lost, loss[kMaxMaterials], add[kMaxMaterials];
    for (int k = 0; k < M; ++k) {
      loss[k] = ke_in[k] - 0.5 * mk_new[k] * u2;
      heat += loss[k];
    }
    // a cell of one material (most of the domain) keeps its own heat: what shareHeat gives it too,
    // to the bit, without its loops
    int held_by = -1, holders = 0;
    for (int k = 0; k < M; ++k)
      if (mk_new[k] > 0.0) {
        held_by = k;
        ++holders;
      }
    if (holders == 1 && lost == 0.0) {
      for (int k = 0; k < M; ++k) add[k] = k == held_by ? heat : 0.0;
    } else {
      shareHeat(M, mk_new, loss, heat, ie_new, add);
    }
    const double V = P.vol[si];
    bool ok = m > 0.0 && std::isfinite(m);
    // Fragments under fragment_fold of the cell go to its other materials (foldFragments), their
    // mass booked by the run's index. The remap's profile never takes a fraction to zero (traces
    // down to 1e-50 spread over the mesh), and every trace costs its pencil the material in every
    // kernel. History and stress stay each material's own (mk_own: its mass before the fold).
    double mk_own[kMaxMaterials];
    for (int k = 0; k < M; ++k) {
      mk_own[k] = mk_new[k];
      ie_new[k] += add[k];
    }
    if (opt_.fragment_fold > 0.0 && holders > 1) {
      double folded[kMaxMaterials];
      foldFragments(M, opt_.fragment_fold, vs, vk_new, mk_new, ie_new, folded);
      for (int k = 0; k < M; ++k) ledger.folded_mass[P.mat[k]] += folded[k];
    }
    for (int k = 0; k < M; ++k) {
      auto& F = fields_[static_cast<std::size_t>(P.mat[k])];
      const std::size_t ki = P.at(k, i), kf = P.atFace(k, i);
      if (mk_new[k] <= 0.0) {
        if (P.a[ki] > 0.0) F.clearCell(c);   // absent before too: clear already (gatherPencil)
        continue;
      }
      // a cell of one material: x / x without the division (a non-finite or zero sum still gives NaN below)
      const double al = vk_new[k] == vs && vs > 0.0 && vs < std::numeric_limits<double>::infinity() ? 1.0 : vk_new[k] / vs;
      F.alpha[c] = al;
      F.rho[c] = mk_new[k] / (al * V);
      F.e[c] = ie_new[k] / mk_new[k];
      // history and deviatoric stress are the material's own: the fragments' do not mix in
      const Reciprocal per_own(mk_own[k]);
      F.h0[c] = per_own.of(P.h[ki] * P.mk[ki] + P.fh[kf] - P.fh[kf + 1]);
      if (!F.s[0].empty())
        for (std::size_t q = 0; q < 6; ++q) F.s[q][c] = per_own.of(P.s[q][ki] * P.mk[ki] + P.fs[q][kf] - P.fs[q][kf + 1]);
      ok = ok && std::isfinite(F.rho[c]) && F.rho[c] > 0.0 && std::isfinite(F.e[c]);
    }
    for (std::size_t q = 0; q < 3; ++q) {
      u_[q][c] = u_new[q];
      ok = ok && std::isfinite(u_[q][c]);
    }
    if (!ok && c < bad) bad = c;
  }
  return bad;
}

void Solver::sweep(int d, double dt) {
  if (exchange_) exchangeHalo(false);   // the neighbours' cells first: the boundaries' ghosts copy them at the corners
  fillGhosts(d);
  interfaceWeights(d);
  if (exchange_ && d == 0) exchangeHalo(true);   // the axis-0 sweep reads the weights in its ghost cells
  const int n = grid_.cells(d), g = kGhost;
  const int M = materialCount();
  SweepSetup S;
  S.d = d;
  S.t1 = (d + 1) % 3;
  S.t2 = (d + 2) % 3;
  const int n1 = grid_.cells(S.t1), n2 = grid_.cells(S.t2);
  S.dt = dt;
  S.materials = M;
  S.second_order = opt_.second_order;
  S.thinc_beta = opt_.thinc_beta;
  S.mixture_reuss = opt_.mixture_reuss;
  S.thinc_bvd = opt_.thinc_bvd;
  S.gravity = opt_.gravity[static_cast<std::size_t>(d)];
  S.wall_velocity = body_velocity_;
  S.friction = body_.empty() ? 0.0 : opt_.body_friction;
  S.load_reference = opt_.load_reference_pressure;
  // Geometry along the sweep axis is the same for every pencil.
  const int Nl = n + 2 * g;
  std::vector<double> line_xc(static_cast<std::size_t>(Nl)), line_w(static_cast<std::size_t>(Nl)), line_rf(static_cast<std::size_t>(Nl) + 1),
      line_inv(static_cast<std::size_t>(Nl), 0.0);
  for (int i = 0; i <= Nl; ++i) {
    line_rf[static_cast<std::size_t>(i)] = grid_.face(d, i - g);
    if (i == Nl) break;
    line_xc[static_cast<std::size_t>(i)] = grid_.centre(d, i - g);
    line_w[static_cast<std::size_t>(i)] = grid_.width(d, i - g);
    if (i > 0) line_inv[static_cast<std::size_t>(i)] = 1.0 / (line_xc[static_cast<std::size_t>(i)] - line_xc[static_cast<std::size_t>(i - 1)]);
  }
  S.xc = line_xc.data();
  S.width = line_w.data();
  S.xf = line_rf.data();
  S.inv_dx = line_inv.data();
  // A body that moves the mesh: this sweep remaps onto the faces moved with it.
  std::vector<double> line_gd(static_cast<std::size_t>(Nl) + 1, 0.0);
  std::optional<mesh::Axis> moved;
  const double offset_after = d == mesh_axis_ ? body_offset_ + body_velocity_[static_cast<std::size_t>(d)] * dt : body_offset_;
  if (d == mesh_axis_ && offset_after != body_offset_) {
    moved = movedAxis(offset_after);
    for (int f = 0; f <= n; ++f) line_gd[static_cast<std::size_t>(f + g)] = moved->faces()[static_cast<std::size_t>(f)] - grid_.face(d, f);
  }
  S.grid_disp = line_gd.data();
  if (d == 0) {
    S.lo_is_boundary = !halo_lo_;
    S.hi_is_boundary = !halo_hi_;
  }
  S.lo_ghosts_copy = opt_.boundary[static_cast<std::size_t>(d)][0] == BoundaryKind::Transmit;
  S.hi_ghosts_copy = opt_.boundary[static_cast<std::size_t>(d)][1] == BoundaryKind::Transmit;
  // Each pencil books its own energy and impulse; they are summed in pencil order afterwards,
  // so the result does not depend on the number of threads.
  // The ledgers (about 1 KB a pencil) are kept from sweep to sweep: allocated anew, every sweep of
  // a 3D mesh paid the kernel's page faults for megabytes. Each pencil clears its own before use.
  auto& ledgers = ledgers_;
  ledgers.resize(static_cast<std::size_t>(n1) * static_cast<std::size_t>(n2));
  for (auto& l : ledgers) l.events = nullptr;
  // a slab logs the body's load by pencil, keyed by the pencil's place in the whole domain's order
  std::vector<std::vector<double>> events(exchange_ ? ledgers.size() : 0);
  if (exchange_) {
    const double n_t2 = S.t2 == 0 ? grid_.globalCells0() : grid_.cells(S.t2);
    const int off1 = S.t1 == 0 ? grid_.offset0() : 0, off2 = S.t2 == 0 ? grid_.offset0() : 0;
    for (int a = 0; a < n1; ++a)
      for (int b = 0; b < n2; ++b) {
        auto& l = ledgers[static_cast<std::size_t>(a) * static_cast<std::size_t>(n2) + static_cast<std::size_t>(b)];
        l.events = &events[static_cast<std::size_t>(a) * static_cast<std::size_t>(n2) + static_cast<std::size_t>(b)];
        l.key = static_cast<double>(a + off1) * n_t2 + static_cast<double>(b + off2);
      }
  }
  // Neighbouring pencils share cache lines only along the contiguous transverse axis: walk that
  // one innermost, so that a line fetched for one pencil serves the next ones (in 3D the sweep along
  // axis 1 otherwise jumped a whole plane between pencils and used one cell of each line). Each
  // pencil writes only its own cells and books into its own ledger, so the order changes no number.
  // (In 2D the third axis is one cell thick, with the same stride as the second: the second is inner.)
  const bool a_inner = grid_.stride(S.t1) < grid_.stride(S.t2) || n2 == 1;
  const int n_outer = a_inner ? n2 : n1, n_inner = a_inner ? n1 : n2;
  // Along a strided axis, neighbouring pencils go as a tile through a staged copy of their cells
  // (stageTile); along the contiguous one each pencil's cells are one run of memory already.
  const bool tiled = opt_.sweep_tile > 1 && grid_.stride(d) != 1 && grid_.stride(a_inner ? S.t1 : S.t2) == 1 && n_inner > 1;
  const int tile = tiled ? std::min(opt_.sweep_tile, kMaxSweepTile) : 1;
  const std::size_t bad_cell = parallel::forEachTile<SweepScratch>(
      n_outer, n_inner, tile, useThreads(), sweep_balance_[static_cast<std::size_t>(d)], [&](SweepScratch& T) { T.pencil.resize(n, M); },
      [&](SweepScratch& T, int outer, int inner_from, int inner_to) {
        // the pencil's place on the two transverse axes, and its first (ghost) cell
        int a_of[kMaxSweepTile] = {}, b_of[kMaxSweepTile] = {};
        std::size_t bases[kMaxSweepTile] = {};
        for (int inner = inner_from; inner < inner_to; ++inner) {
          const int t = inner - inner_from;
          a_of[t] = a_inner ? inner : outer;
          b_of[t] = a_inner ? outer : inner;
          int idx[3];
          idx[d] = -g;
          idx[S.t1] = a_of[t];
          idx[S.t2] = b_of[t];
          bases[t] = grid_.index(idx[0], idx[1], idx[2]);
        }
        if (tiled) stageTile(T, d, bases, inner_to - inner_from, T.pencil.N);
        std::size_t bad = std::numeric_limits<std::size_t>::max();
        Pencil& P = T.pencil;
        for (int inner = inner_from; inner < inner_to; ++inner) {
          const int t = inner - inner_from, a = a_of[t], b = b_of[t];
          const std::size_t base = bases[t];
          const PencilSource src = tiled ? T.sources[static_cast<std::size_t>(t)] : meshSource(d, base);
          auto& ledger = ledgers[static_cast<std::size_t>(a) * static_cast<std::size_t>(n2) + static_cast<std::size_t>(b)];
          ledger.clearBooks();
          selectMaterials(P, src);
          gatherPencil(P, d, src, a, b, S);
          computeSlopes(P, S);
          solveFaces(P, S, ledger);
          lagrangeUpdate(P, S, ledger);
          remapFluxes(P, S, ledger);
          if (moved) moveCellVolumes(P, S);
          bad = std::min(bad, scatterPencil(P, d, base, ledger));
        }
        return bad;
      });
  if (tiled) stats_.staged_tiles += static_cast<std::int64_t>(n_outer) * ((n_inner + tile - 1) / tile);
  if (moved) {
    grid_.moveFaces(d, std::move(*moved));
    body_offset_ = offset_after;
  }
  if (exchange_) {   // every slab sees the same load, summed as the whole would sum it
    std::vector<double> mine;
    for (const auto& e : events) mine.insert(mine.end(), e.begin(), e.end());
    combineBodyLoad(mine);
    for (auto& l : ledgers) l.events = nullptr;
  }
  for (const auto& l : ledgers) {
    energy_.boundary_in += l.boundary_in;
    energy_.target_work += l.target_work;
    energy_.gravity_work += l.gravity_work;
    for (int k = 0; k < M; ++k) {
      energy_.folded_mass[static_cast<std::size_t>(k)] += l.folded_mass[k];
      energy_.boundary_mass[static_cast<std::size_t>(k)] += l.boundary_mass[k];
    }
    if (exchange_) continue;
    // the total from the stress itself: the by-material split is against the reference pressure,
    // which cancels over the plate's top and bottom but not over a rim or a symmetry-plane cut
    for (std::size_t q = 0; q < 3; ++q) body_impulse_[q] += l.impulse_total[q];
    if (!body_impulse_mat_.empty())
      for (int k = 0; k < M; ++k)
        for (std::size_t q = 0; q < 3; ++q) {
          body_impulse_mat_[static_cast<std::size_t>(k)][q] += l.impulse_on_body[k][q];
          for (int w = 0; w < kNearWallDepths; ++w)
            body_impulse_near_[static_cast<std::size_t>(w)][static_cast<std::size_t>(k)][q] += l.impulse_near_body[w][k][q];
        }
  }
  const bool bad_here = bad_cell != std::numeric_limits<std::size_t>::max();
  if (exchange_ && exchange_->minimum(bad_here ? 0.0 : 1.0) < 0.5 && !bad_here)   // every slab stops together
    throw RunError(fmt::format("another slab of the domain failed at t = {:.6g} s, step {}", time_, step_));
  if (bad_here) checkCell(bad_cell, d == 0 ? "sweep along axis 0" : (d == 1 ? "sweep along axis 1" : "sweep along axis 2"));
}

void Solver::checkCell(std::size_t cell, const char* stage) const {
  const auto ix = grid_.unflatten(cell);
  std::string what = "non-finite velocity";
  std::string mat = "mixture";
  for (std::size_t k = 0; k < mats_.size(); ++k) {
    const auto& f = fields_[k];
    if (f.alpha[cell] <= 0.0) continue;
    if (!std::isfinite(f.rho[cell]) || !(f.rho[cell] > 0.0)) {
      what = fmt::format("density {:g} kg/m3", f.rho[cell]);
      mat = mats_[k].name;
      break;
    }
    if (!std::isfinite(f.e[cell])) {
      what = fmt::format("internal energy {:g} J/kg", f.e[cell]);
      mat = mats_[k].name;
      break;
    }
  }
  throw RunError(fmt::format("{} in cell ({}, {}, {}) at x = ({:.4g}, {:.4g}, {:.4g}) m, material {}, t = {:.6g} s, step {} ({})",
                             what, ix.i + grid_.offset0(), ix.j, ix.k, grid_.centre(0, ix.i), grid_.centre(1, ix.j), grid_.centre(2, ix.k), mat,
                             time_, step_, stage));
}

// ------------------------------------------------------------------------------------------------

void Solver::step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw RunError(fmt::format("invalid time step {:g} s at t = {:.6g} s", dt, time_));
  body_impulse_ = Vec3{};
  for (auto& v : body_impulse_mat_) v = Vec3{};
  for (auto& layer : body_impulse_near_)
    for (auto& v : layer) v = Vec3{};
  updateBurn(dt);
  updateStress(dt);
  const int dims = grid_.dims();
  for (int s = 0; s < dims; ++s) {
    const int d = (step_ % 2 == 0) ? s : dims - 1 - s;
    sweep(d, dt);
  }
  time_ += dt;
  last_dt_ = dt;
  ++step_;
  stats_.steps = step_;
  stats_.cell_updates += static_cast<double>(grid_.interiorCells());
}

void Solver::startAt(double t, const EnergyLedger& booked) {
  time_ = t;
  last_dt_ = 0.0;
  dt_free_ = 0.0;   // a mapped state starts its steps afresh
  energy_.boundary_in += booked.boundary_in;
  energy_.target_work += booked.target_work;
  energy_.gravity_work += booked.gravity_work;
  for (std::size_t k = 0; k < energy_.folded_mass.size(); ++k) {
    energy_.folded_mass[k] += booked.folded_mass[k];
    energy_.boundary_mass[k] += booked.boundary_mass[k];
  }
}

// The load at rest as (axis, term) pairs in the whole's order of cells and faces: a slab takes the
// faces whose flow cell is in a neighbouring slab too (its ghosts, exchanged), so that the slabs'
// lists in rank order are the whole's list.
std::vector<double> Solver::bodyLoadTerms() const {
  std::vector<double> terms;
  if (body_.empty()) return terms;
  const int off0 = grid_.offset0(), n0 = grid_.globalCells0();
  for (int i = 0; i < grid_.cells(0); ++i)
    for (int j = 0; j < grid_.cells(1); ++j)
      for (int k = 0; k < grid_.cells(2); ++k) {
        const std::size_t c = grid_.index(i, j, k);
        if (!body_[c]) continue;
        for (int d = 0; d < grid_.dims(); ++d)
          for (int side = 0; side < 2; ++side) {
            int idx[3] = {i, j, k};
            idx[d] += side == 0 ? -1 : 1;
            // as the sweep: a ghost neighbour is the boundary's (along axis 0, the whole's boundary)
            const int along = d == 0 ? idx[0] + off0 : idx[d], n = d == 0 ? n0 : grid_.cells(d);
            if (along < 0 || along >= n) continue;
            const std::size_t nb = grid_.index(idx[0], idx[1], idx[2]);
            if (body_[nb]) continue;
            double rho = 0.0, p = 0.0, kv = 0.0, snn = 0.0, pmin = 0.0;
            for (std::size_t q = 0; q < mats_.size(); ++q) {
              const auto& F = fields_[q];
              if (F.alpha[nb] <= 0.0) continue;
              const auto st = materials::evaluateEos(mats_[q], F.rho[nb], F.e[nb], F.h0[nb]);
              rho += F.alpha[nb] * F.rho[nb];
              p += F.alpha[nb] * st.pressure;
              kv += F.alpha[nb] * st.bulk;
              pmin += F.alpha[nb] * materials::tensionLimit(mats_[q]);
              if (!F.s[0].empty()) snn += F.alpha[nb] * F.s[static_cast<std::size_t>(d)][nb];
            }
            const double z = std::sqrt(std::max(rho * kv, 1e-30));
            const double un = u_[static_cast<std::size_t>(d)][nb], uw = body_velocity_[static_cast<std::size_t>(d)];
            // fluid below the body (side 0) pushes it up the axis; above, down
            const double ps = std::max(side == 0 ? (p - snn) + z * (un - uw) : (p - snn) + z * (uw - un), pmin);
            const double area = side == 0 ? grid_.faceArea(d, i, j, k) : grid_.faceArea(d, idx[0], idx[1], idx[2]);
            terms.push_back(d);
            terms.push_back((side == 0 ? 1.0 : -1.0) * ps * area);
          }
      }
  return terms;
}

namespace {
Vec3 sumBodyLoadTerms(const std::vector<double>& terms) {
  Vec3 f{};
  for (std::size_t t = 0; t + 1 < terms.size(); t += 2) f[static_cast<std::size_t>(terms[t])] += terms[t + 1];
  return f;
}
}  // namespace

Vec3 Solver::bodyLoad() const { return sumBodyLoadTerms(bodyLoadTerms()); }

Vec3 Solver::wholeBodyLoad() {
  if (!exchange_ || exchange_->size() == 1) return bodyLoad();
  exchangeHalo(false);   // the faces whose flow cell is the neighbour's
  return sumBodyLoadTerms(exchange_->gatherAll(bodyLoadTerms()));
}

double Solver::nextTimeStep(double stop) {
  double dt = stableTimeStep();
  dt = dt_free_ > 0.0 ? std::min(dt, 1.2 * dt_free_) : dt * opt_.initial_dt_fraction;
  dt = std::min(dt, opt_.max_dt);
  dt_free_ = dt;
  dt = std::min(dt, stop - time_);
  if (!(dt >= opt_.min_dt) && stop - time_ > opt_.min_dt)   // name the cell that forces the step down
    throw RunError(fmt::format("time step collapsed to {:g} s (limit {:g} s) at t = {:.6g} s, step {}; {}", dt, opt_.min_dt, time_, step_,
                               describeLimitingCell()));
  return dt;
}

void Solver::advanceTo(double t_end, const std::function<void(const Solver&)>& on_step) {
  const auto t0 = std::chrono::steady_clock::now();
  while (time_ < t_end * (1.0 - 1e-14)) {
    step(nextTimeStep(t_end));
    if (on_step) on_step(*this);
  }
  stats_.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace ejecta::hydro
