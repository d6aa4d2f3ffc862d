#include "hydro/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <istream>
#include <limits>
#include <ostream>

#include <fmt/format.h>

#include "core/error.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace ejecta::hydro {

using materials::EosKind;
using materials::StrengthKind;
using mesh::BoundaryKind;
using mesh::kGhost;

namespace {
constexpr double kAlphaMin = 1e-8;    // below this a material is a fragment: it rides along
constexpr double kPureCell = 1.0 - 1e-9;
constexpr double kAdiabatMinAlpha = 1e-3;   // products' adiabat is enforced from this volume fraction up

inline double vanLeer(double a, double b) { return a * b > 0.0 ? 2.0 * a * b / (a + b) : 0.0; }

inline double lnCosh(double x) {
  const double ax = std::abs(x);
  return ax + std::log1p(std::exp(-2.0 * ax)) - 0.69314718055994530942;
}

// Fraction of the donor's volume that is material k and leaves through the face, for a swept
// fraction b of the donor, from a THINC (tanh) profile fitted to the cell mean and oriented by
// the neighbours (Xiao, Honma & Kono 2005). Falls back to the donor mean where the neighbours do
// not bracket the cell (no interface to sharpen).
inline double thincOutflow(double a, double a_lo, double a_hi, double b, bool out_high, double beta) {
  const double hi_cap = std::min(a, b), lo_cap = std::max(0.0, a - (1.0 - b));
  if (a < 1e-6 || a > 1.0 - 1e-6 || (a_hi - a) * (a - a_lo) <= 0.0) return std::clamp(a * b, lo_cap, hi_cap);
  const double gamma = a_hi > a_lo ? 1.0 : -1.0;
  const double q = 2.0 * beta * gamma * (a - 0.5);   // gamma = +-1, so 1/gamma = gamma
  const double t = (std::exp(beta) - std::exp(q)) / (std::exp(q) - std::exp(-beta));
  const double xc = std::log(t) / (2.0 * beta);
  double f;
  if (out_high)
    f = 0.5 * b + gamma / (2.0 * beta) * (lnCosh(beta * (1.0 - xc)) - lnCosh(beta * (1.0 - b - xc)));
  else
    f = 0.5 * b + gamma / (2.0 * beta) * (lnCosh(beta * (b - xc)) - lnCosh(beta * xc));
  return std::clamp(f, lo_cap, hi_cap);
}
}  // namespace

// Scratch of one pencil (a line of cells along the sweep axis, ghosts included). Per-material
// arrays are [k * N + i].
struct Solver::Pencil {
  int n = 0, N = 0, M = 0;
  bool radial = false;       // axisymmetric r-sweep: swept volumes are annuli
  double ring_width = 0.0;   // axisymmetric r-sweep: the cell's z width
  std::vector<double> vol, area;
  std::array<std::vector<double>, 3> u;   // velocity components (global axes)
  std::vector<double> rho, P, K, Z, hoop;
  std::array<std::vector<double>, 2> shear;   // mixture s_{d,t} for the two transverse axes
  std::vector<double> a, r, e, h, ad, pk, kk, wl;
  std::array<std::vector<double>, 6> s;
  // faces
  std::vector<double> ustar, pstar, dvol;
  // Lagrangian cells
  std::vector<double> vlag, mass, ke;
  std::array<std::vector<double>, 3> mom;
  std::vector<double> vk, mk, iek;
  // remap fluxes at faces (signed, + along the axis)
  std::vector<double> fv, fm, fe, fh, fa;
  std::array<std::vector<double>, 6> fs;
  std::array<std::vector<double>, 3> fmom;
  std::vector<double> fke;
  std::vector<double> su, sp;   // limited slopes of normal velocity and normal stress
  std::vector<unsigned char> solid;

  void resize(int cells, int materials) {
    n = cells;
    N = cells + 2 * kGhost;
    M = materials;
    const auto sN = static_cast<std::size_t>(N), sF = sN + 1, sMN = sN * static_cast<std::size_t>(M),
               sMF = sF * static_cast<std::size_t>(M);
    for (auto* v : {&vol, &rho, &P, &K, &Z, &hoop, &vlag, &mass, &ke, &su, &sp}) v->assign(sN, 0.0);
    for (auto* v : {&area, &ustar, &pstar, &dvol, &fke}) v->assign(sF, 0.0);
    for (auto& v : u) v.assign(sN, 0.0);
    for (auto& v : mom) v.assign(sN, 0.0);
    for (auto& v : shear) v.assign(sN, 0.0);
    for (auto& v : fmom) v.assign(sF, 0.0);
    for (auto* v : {&a, &r, &e, &h, &ad, &pk, &kk, &wl, &vk, &mk, &iek}) v->assign(sMN, 0.0);
    for (auto& v : s) v.assign(sMN, 0.0);
    for (auto* v : {&fv, &fm, &fe, &fh, &fa}) v->assign(sMF, 0.0);
    for (auto& v : fs) v.assign(sMF, 0.0);
    solid.assign(sN, 0);
  }
};

Solver::Solver(mesh::Grid grid, std::vector<materials::Material> materials, SolverOptions options)
    : grid_(std::move(grid)), mats_(std::move(materials)), opt_(std::move(options)) {
  if (mats_.empty() || mats_.size() > 8) throw InputError("materials", fmt::format("{} given; valid 1 to 8", mats_.size()));
  for (const auto& m : mats_) {
    m.validate();
    any_strength_ = any_strength_ || m.hasStrength();
  }
  if (!(opt_.cfl > 0.0 && opt_.cfl <= 0.9)) throw InputError("cfl", fmt::format("{:g} is out of range; valid (0, 0.9]", opt_.cfl));
  if (grid_.axisymmetric() && opt_.boundary[0][0] != BoundaryKind::Reflect && grid_.axis(0).lo() == 0.0)
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
  isentropes_.resize(mats_.size());
  if (opt_.products_adiabat)
    for (std::size_t k = 0; k < mats_.size(); ++k)
      if (mats_[k].eos == EosKind::Jwl) {
        isentropes_[k] = std::make_shared<const materials::JwlIsentrope>(mats_[k].jwl);
        fields_[k].adiabat.assign(total, 0.0);
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

void Solver::paint(int mat, const std::function<bool(const Vec3&)>& inside, double rho, double e, Vec3 u, int sub) {
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
              const double wgt = grid_.axisymmetric() ? x[0] : 1.0;
              all += wgt;
              if (inside(x)) in += wgt;
            }
        const double f = all > 0.0 ? in / all : 0.0;
        if (f <= 0.0) continue;
        const std::size_t cell = grid_.index(i, j, k);
        for (std::size_t q = 0; q < fields_.size(); ++q) fields_[q].alpha[cell] *= (1.0 - f);
        F.alpha[cell] += f;
        F.rho[cell] = rho;
        F.e[cell] = e;
        F.h0[cell] = 0.0;
        if (!F.adiabat.empty()) F.adiabat[cell] = 0.0;
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
    if (grid_.axisymmetric()) x[0] = std::abs(x[0]);   // the axis ghosts mirror the body
    body_[c] = inside(x) ? 1 : 0;
  }
  body_impulse_mat_.assign(mats_.size(), Vec3{});
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
    if (!f.adiabat.empty()) putVec(os, f.adiabat);
  }
  for (const auto& c : u_) putVec(os, c);
  putRaw(os, adiabat_sink_);
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
    if (!f.adiabat.empty()) getVec(is, f.adiabat);
  }
  for (auto& c : u_) getVec(is, c);
  getRaw(is, adiabat_sink_);
  if (!is) throw InputError("restart", "the checkpoint is truncated");
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

Totals Solver::totals() const {
  Totals t;
  t.mass.assign(mats_.size(), 0.0);
  t.adiabat_sink = adiabat_sink_;
  for (int i = 0; i < grid_.cells(0); ++i)
    for (int j = 0; j < grid_.cells(1); ++j)
      for (int k = 0; k < grid_.cells(2); ++k) {
        const std::size_t c = grid_.index(i, j, k);
        if (isBody(c)) continue;
        const double v = grid_.cellVolume(i, j, k);
        double m = 0.0;
        for (std::size_t q = 0; q < fields_.size(); ++q) {
          const double mq = fields_[q].alpha[c] * fields_[q].rho[c] * v;
          t.mass[q] += mq;
          t.internal_energy += mq * fields_[q].e[c];
          m += mq;
        }
        for (std::size_t d = 0; d < 3; ++d) {
          t.momentum[d] += m * u_[d][c];
          t.kinetic_energy += 0.5 * m * u_[d][c] * u_[d][c];
        }
      }
  return t;
}

// The signal speed of one cell: the mixture's (volume-averaged stiffness over mixture density),
// and each material's own where it holds at least 1% of the cell's mass. A nearly massless
// material's own sound speed (a hot, rarefied film of air in the products; products expanded into
// a void that the sand opened in tension: 1e5 to 1e7 m/s) does not govern stability: its volume
// follows the cell's, and no wave runs inside it.
static double cellSignalSpeed2(const std::vector<materials::Material>& mats, const std::vector<MaterialFields>& fields, std::size_t c) {
  double c2 = 0.0, kv = 0.0, rho_mix = 0.0;
  for (const auto& f : fields) rho_mix += f.alpha[c] * f.rho[c];
  for (std::size_t q = 0; q < fields.size(); ++q) {
    const auto& f = fields[q];
    if (f.alpha[c] <= kAlphaMin) continue;
    const auto st = materials::evaluateEos(mats[q], f.rho[c], f.e[c], f.h0[c]);
    double kk = st.bulk;
    if (mats[q].hasStrength()) {
      const double g = mats[q].strength.kind == StrengthKind::VonMises ? mats[q].strength.shear_modulus : mats[q].sand->shearModulus(f.h0[c]);
      kk += 4.0 / 3.0 * g;
    }
    kv += f.alpha[c] * kk;
    if (f.alpha[c] * f.rho[c] >= 0.01 * rho_mix) c2 = std::max(c2, kk / f.rho[c]);
  }
  return std::max(c2, kv / rho_mix);
}

double Solver::stableTimeStep() const {
  double dt = std::numeric_limits<double>::infinity();
  const int n0 = grid_.cells(0), n1 = grid_.cells(1), n2 = grid_.cells(2), dims = grid_.dims();
#pragma omp parallel for collapse(2) reduction(min : dt) schedule(static)
  for (int i = 0; i < n0; ++i)
    for (int j = 0; j < n1; ++j)
      for (int k = 0; k < n2; ++k) {
        const std::size_t c = grid_.index(i, j, k);
        if (isBody(c)) continue;
        const double cs = std::sqrt(cellSignalSpeed2(mats_, fields_, c));
        const int idx[3] = {i, j, k};
        for (int d = 0; d < dims; ++d)
          dt = std::min(dt, grid_.width(d, idx[d]) / (std::abs(u_[static_cast<std::size_t>(d)][c]) + cs + 1e-30));
      }
  return opt_.cfl * dt;
}

std::string Solver::describeLimitingCell() const {
  double best = std::numeric_limits<double>::infinity();
  std::size_t cell = 0;
  for (int i = 0; i < grid_.cells(0); ++i)
    for (int j = 0; j < grid_.cells(1); ++j)
      for (int k = 0; k < grid_.cells(2); ++k) {
        const std::size_t c = grid_.index(i, j, k);
        if (isBody(c)) continue;
        const double cs = std::sqrt(cellSignalSpeed2(mats_, fields_, c));
        const int idx[3] = {i, j, k};
        for (int d = 0; d < grid_.dims(); ++d) {
          const double t = grid_.width(d, idx[d]) / (std::abs(u_[static_cast<std::size_t>(d)][c]) + cs + 1e-30);
          if (t < best) {
            best = t;
            cell = c;
          }
        }
      }
  const auto ix = grid_.unflatten(cell);
  std::string s = fmt::format("limited by cell ({}, {}, {}) at x = ({:.4g}, {:.4g}, {:.4g}) m, velocity ({:.4g}, {:.4g}, {:.4g}) m/s:", ix.i, ix.j, ix.k,
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

void Solver::fillGhosts(int d) {
  if (d >= grid_.dims()) return;
  const int n = grid_.cells(d);
  const int t1 = (d + 1) % 3, t2 = (d + 2) % 3;
  const int lo1 = -grid_.ghost(t1), hi1 = grid_.cells(t1) + grid_.ghost(t1);
  const int lo2 = -grid_.ghost(t2), hi2 = grid_.cells(t2) + grid_.ghost(t2);
  auto at = [&](int along, int a, int b) {
    int idx[3];
    idx[d] = along;
    idx[t1] = a;
    idx[t2] = b;
    return grid_.index(idx[0], idx[1], idx[2]);
  };
  for (int side = 0; side < 2; ++side) {
    const BoundaryKind kind = opt_.boundary[static_cast<std::size_t>(d)][static_cast<std::size_t>(side)];
    for (int a = lo1; a < hi1; ++a)
      for (int b = lo2; b < hi2; ++b)
        for (int q = 0; q < kGhost; ++q) {
          const int ghost = side == 0 ? -1 - q : n + q;
          int src = 0;
          switch (kind) {
            case BoundaryKind::Reflect: src = side == 0 ? q : n - 1 - q; break;
            case BoundaryKind::Transmit: src = side == 0 ? 0 : n - 1; break;
            case BoundaryKind::Periodic: src = side == 0 ? n - 1 - q : q; break;
          }
          src = std::clamp(src, 0, n - 1);
          const std::size_t g = at(ghost, a, b), s = at(src, a, b);
          for (std::size_t k = 0; k < fields_.size(); ++k) {
            auto& f = fields_[k];
            f.alpha[g] = f.alpha[s];
            f.rho[g] = f.rho[s];
            f.e[g] = f.e[s];
            f.h0[g] = f.h0[s];
            if (!f.adiabat.empty()) f.adiabat[g] = f.adiabat[s];
            if (!f.s[0].empty())
              for (int c = 0; c < 6; ++c) f.s[static_cast<std::size_t>(c)][g] = f.s[static_cast<std::size_t>(c)][s];
            if (kind == BoundaryKind::Reflect && !f.s[0].empty())
              for (int t = 0; t < 3; ++t)
                if (t != d) f.s[static_cast<std::size_t>(stressIndex(d, t))][g] = -f.s[static_cast<std::size_t>(stressIndex(d, t))][s];
          }
          for (std::size_t c = 0; c < 3; ++c) u_[c][g] = u_[c][s];
          if (kind == BoundaryKind::Reflect) u_[static_cast<std::size_t>(d)][g] = -u_[static_cast<std::size_t>(d)][s];
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
#pragma omp parallel for collapse(2) schedule(static)
  for (int i = 0; i < n0; ++i)
    for (int j = 0; j < n1; ++j)
      for (int k = 0; k < n2; ++k) {
        const std::size_t c = grid_.index(i, j, k);
        const int idx[3] = {i, j, k};
        for (int m = 0; m < M; ++m) {
          const auto& al = fields_[static_cast<std::size_t>(m)].alpha;
          double& w = wlic_[static_cast<std::size_t>(m) * total + c];
          if (al[c] <= 0.0 || al[c] >= 1.0) {
            w = 1.0;
            continue;
          }
          double nd = 0.0, nsum = 0.0;
          for (int b = 0; b < dims; ++b) {
            int lo[3] = {i, j, k}, hi[3] = {i, j, k};
            lo[b] -= 1;
            hi[b] += 1;
            const double g = std::abs((al[grid_.index(hi[0], hi[1], hi[2])] - al[grid_.index(lo[0], lo[1], lo[2])]) /
                                      (grid_.centre(b, idx[b] + 1) - grid_.centre(b, idx[b] - 1)));
            nsum += g;
            if (b == d) nd = g;
          }
          w = nsum > 0.0 ? nd / nsum : 1.0;
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
    const auto* isentrope = isentropes_[k].get();
    // Products that finish burning start on the CJ isentrope, as an ideal detonation leaves them
    // (products_adiabat): the programmed burn's own heating goes to the sink. Partial sums per
    // row of the outermost axis, added in order, keep the sink independent of the thread count.
    const int n0 = grid_.cells(0), n1 = grid_.cells(1), n2 = grid_.cells(2);
    std::vector<double> row_sink(isentrope ? static_cast<std::size_t>(n0) : 0, 0.0);
#pragma omp parallel for schedule(static)
    for (int i = 0; i < n0; ++i)
      for (int jj = 0; jj < n1; ++jj)
        for (int kk = 0; kk < n2; ++kk) {
          const std::size_t c = grid_.index(i, jj, kk);
          if (f.alpha[c] <= 0.0 || f.h0[c] >= 1.0) continue;
          const double lit = light_delay_[c] + light_distance_[c] / j.d_cj;
          const double frac = std::clamp((t - lit) * j.d_cj / (j.burn_width * burn_length_[c]), 0.0, 1.0);
          f.h0[c] = std::max(f.h0[c], frac);
          if (isentrope && f.h0[c] >= 1.0 && materials::JwlIsentrope::covers(j.rho0 / f.rho[c])) {
            const double e_cj = isentrope->energy(j.rho0 / f.rho[c]) / j.rho0;
            row_sink[static_cast<std::size_t>(i)] += f.alpha[c] * f.rho[c] * grid_.cellVolume(i, jj, kk) * (f.e[c] - e_cj);
            f.e[c] = e_cj;
            f.adiabat[c] = 0.0;
          }
        }
    for (const double e : row_sink) adiabat_sink_ += e;
  }
}

// ------------------------------------------------------------------------------------------------
// Deviatoric stress: hypoelastic with Jaumann rotation, radial return to the yield surface.

void Solver::updateStress(double dt) {
  if (!any_strength_) return;
  for (int d = 0; d < grid_.dims(); ++d) fillGhosts(d);
  const int dims = grid_.dims();
  const bool axi = grid_.axisymmetric();
  const int n0 = grid_.cells(0), n1 = grid_.cells(1), n2 = grid_.cells(2);
#pragma omp parallel for collapse(2) schedule(static)
  for (int i = 0; i < n0; ++i)
    for (int j = 0; j < n1; ++j)
      for (int k = 0; k < n2; ++k) {
        const std::size_t c = grid_.index(i, j, k);
        bool any = false;
        for (std::size_t q = 0; q < mats_.size(); ++q) any = any || (mats_[q].hasStrength() && fields_[q].alpha[c] > kAlphaMin);
        if (!any) continue;
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
          double G, Y;
          const double p = materials::evaluateEos(m, f.rho[c], f.e[c], f.h0[c]).pressure;
          if (m.strength.kind == StrengthKind::VonMises) {
            G = m.strength.shear_modulus;
            Y = m.strength.yield;
          } else {
            G = m.sand->shearModulus(f.h0[c]);
            Y = std::min(m.sand_slope * std::max(p, 0.0), m.sand_plateau);
          }
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
      }
}

// ------------------------------------------------------------------------------------------------
// One sweep along axis d: Lagrange then remap on every pencil.

void Solver::sweep(int d, double dt) {
  fillGhosts(d);
  interfaceWeights(d);
  const std::size_t total_cells = grid_.totalCells();
  const int n = grid_.cells(d), g = kGhost;
  const int M = materialCount();
  const int t1 = (d + 1) % 3, t2 = (d + 2) % 3;
  const int n1 = grid_.cells(t1), n2 = grid_.cells(t2);
  const bool radial = grid_.axisymmetric() && d == 0;
  const double grav = opt_.gravity[static_cast<std::size_t>(d)];
  const double beta = opt_.thinc_beta;
  const bool second = opt_.second_order;
  const std::ptrdiff_t stride = grid_.stride(d);
  const int s_dt1 = stressIndex(d, t1), s_dt2 = stressIndex(d, t2);
  std::size_t bad_cell = std::numeric_limits<std::size_t>::max();
  // Impulse on the body, per pencil and material (summed in pencil order afterwards, so the result
  // does not depend on the number of threads).
  const bool has_body = !body_.empty();
  const double wall_u = body_velocity_[static_cast<std::size_t>(d)];
  const double friction = opt_.body_friction;
  const bool track = opt_.products_adiabat;
  std::vector<double> pencil_sink(track ? static_cast<std::size_t>(n1) * static_cast<std::size_t>(n2) : 0, 0.0);
  std::vector<double> pencil_impulse(has_body ? static_cast<std::size_t>(n1) * static_cast<std::size_t>(n2) * static_cast<std::size_t>(M) : 0, 0.0);
  // Geometry along the sweep axis is the same for every pencil: centres, widths, faces, and the
  // inverse centre spacings the slopes use.
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

#pragma omp parallel
  {
    Pencil P;
    P.resize(n, M);
    const int N = P.N;
    std::size_t my_bad = std::numeric_limits<std::size_t>::max();
#pragma omp for collapse(2) schedule(static)
    for (int a = 0; a < n1; ++a)
      for (int b = 0; b < n2; ++b) {
        int idx[3];
        idx[d] = -g;
        idx[t1] = a;
        idx[t2] = b;
        const std::size_t base = grid_.index(idx[0], idx[1], idx[2]);
        auto cell = [&](int i) { return static_cast<std::size_t>(static_cast<std::ptrdiff_t>(base) + i * stride); };
        // ---- gather: geometry (areas and volumes from the transverse measure of the pencil)
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
          if (radial) {
            const double rl = line_rf[si];
            P.area[si] = std::abs(rl) * trans;
            if (i < N) {
              const double rr = line_rf[si + 1];
              P.vol[si] = 0.5 * std::abs(rr * std::abs(rr) - rl * std::abs(rl)) * trans;
            }
          } else {
            P.area[si] = trans;
            if (i < N) P.vol[si] = trans * line_w[si];
          }
        }
        P.ring_width = radial ? trans : 0.0;
        P.radial = radial;
        // ---- gather: state and EOS
        for (int i = 0; i < N; ++i) {
          const std::size_t c = cell(i), si = static_cast<std::size_t>(i);
          for (std::size_t q = 0; q < 3; ++q) P.u[q][si] = u_[q][c];
          P.solid[si] = has_body ? body_[c] : 0;
          double rho = 0.0, p = 0.0, kv = 0.0, snn = 0.0, stt = 0.0, sh1 = 0.0, sh2 = 0.0;
          for (int k = 0; k < M; ++k) {
            const auto& F = fields_[static_cast<std::size_t>(k)];
            const auto& mat = mats_[static_cast<std::size_t>(k)];
            const std::size_t ki = static_cast<std::size_t>(k * N + i);
            const double al = F.alpha[c];
            P.a[ki] = al;
            P.wl[ki] = M > 1 ? wlic_[static_cast<std::size_t>(k) * total_cells + c] : 1.0;
            P.r[ki] = F.rho[c];
            P.e[ki] = F.e[c];
            P.ad[ki] = F.adiabat.empty() ? 0.0 : F.adiabat[c];
            double h = F.h0[c];
            if (al > 0.0) {
              const auto st = materials::evaluateEos(mat, F.rho[c], F.e[c], h);
              if (mat.eos == EosKind::Sand) h = std::max(h, std::log(F.rho[c] / mat.sand->referenceDensity()));
              P.pk[ki] = st.pressure;
              P.kk[ki] = st.bulk;
              rho += al * F.rho[c];
              p += al * st.pressure;
              kv += al * st.bulk;
            } else {
              P.pk[ki] = 0.0;
              P.kk[ki] = 0.0;
            }
            P.h[ki] = h;
            if (!F.s[0].empty()) {
              for (std::size_t q = 0; q < 6; ++q) P.s[q][ki] = F.s[q][c];
              snn += al * F.s[static_cast<std::size_t>(d)][c];
              stt += al * F.s[2][c];
              sh1 += al * F.s[static_cast<std::size_t>(s_dt1)][c];
              sh2 += al * F.s[static_cast<std::size_t>(s_dt2)][c];
            }
          }
          P.rho[si] = rho;
          P.P[si] = p - snn;
          P.hoop[si] = p - stt;
          P.K[si] = kv;
          P.Z[si] = std::sqrt(std::max(rho * kv, 1e-30));
          P.shear[0][si] = sh1;
          P.shear[1][si] = sh2;
        }
        const auto& un = P.u[static_cast<std::size_t>(d)];
        // ---- slopes of normal velocity and normal stress (cells 1..N-2)
        for (int i = 1; i < N - 1; ++i) {
          const std::size_t si = static_cast<std::size_t>(i);
          if (!second || (has_body && (P.solid[si - 1] | P.solid[si] | P.solid[si + 1]))) {
            P.su[si] = P.sp[si] = 0.0;   // first order beside the body
            continue;
          }
          const double il = line_inv[si], ir = line_inv[si + 1];
          P.su[si] = vanLeer((un[si] - un[si - 1]) * il, (un[si + 1] - un[si]) * ir);
          P.sp[si] = vanLeer((P.P[si] - P.P[si - 1]) * il, (P.P[si + 1] - P.P[si]) * ir);
        }
        // ---- acoustic Riemann problem at faces g-1 .. g+n+1 with MUSCL-Hancock states
        for (int f = g - 1; f <= g + n + 1; ++f) {
          const std::size_t L = static_cast<std::size_t>(f - 1), R = static_cast<std::size_t>(f);
          const double hl = 0.5 * line_w[L], hr = 0.5 * line_w[R];
          const double uL = un[L] + hl * P.su[L] - 0.5 * dt * P.sp[L] / P.rho[L];
          const double pL = P.P[L] + hl * P.sp[L] - 0.5 * dt * P.K[L] * P.su[L];
          const double uR = un[R] - hr * P.su[R] - 0.5 * dt * P.sp[R] / P.rho[R];
          const double pR = P.P[R] - hr * P.sp[R] - 0.5 * dt * P.K[R] * P.su[R];
          const double zl = P.Z[L], zr = P.Z[R], zs = zl + zr;
          if (has_body && (P.solid[L] | P.solid[R])) {
            // a wall moving with the body: the flow's half of the Riemann problem, no swept volume
            double ps = 0.0;
            if (!P.solid[L]) ps = pL + zl * (uL - wall_u);
            else if (!P.solid[R]) ps = pR + zr * (wall_u - uR);
            P.ustar[static_cast<std::size_t>(f)] = wall_u;
            P.pstar[static_cast<std::size_t>(f)] = ps;
            P.dvol[static_cast<std::size_t>(f)] = 0.0;
            continue;
          }
          const double us = (zl * uL + zr * uR + pL - pR) / zs;
          P.ustar[static_cast<std::size_t>(f)] = us;
          P.pstar[static_cast<std::size_t>(f)] = (zr * pL + zl * pR + zl * zr * (uL - uR)) / zs;
          const double disp = us * dt, rf = line_rf[static_cast<std::size_t>(f)];
          P.dvol[static_cast<std::size_t>(f)] =
              radial ? P.ring_width * 0.5 * ((rf + disp) * std::abs(rf + disp) - rf * std::abs(rf)) : P.area[static_cast<std::size_t>(f)] * disp;
        }
        // ---- the load on the body: faces between a flow cell and an interior body cell
        if (has_body) {
          const std::size_t pencil = static_cast<std::size_t>(a) * static_cast<std::size_t>(n2) + static_cast<std::size_t>(b);
          for (int f = g; f <= g + n; ++f) {
            const std::size_t L = static_cast<std::size_t>(f - 1), R = static_cast<std::size_t>(f);
            if (!(P.solid[L] ^ P.solid[R])) continue;
            const bool body_right = P.solid[R] != 0;
            if ((body_right && f == g + n) || (!body_right && f == g)) continue;   // body cell is a ghost
            const std::size_t fluid = body_right ? L : R;
            const double imp = (body_right ? 1.0 : -1.0) * P.pstar[R] * P.area[R] * dt;
            for (int k = 0; k < M; ++k)
              pencil_impulse[pencil * static_cast<std::size_t>(M) + static_cast<std::size_t>(k)] +=
                  imp * P.a[static_cast<std::size_t>(k * N) + fluid];
          }
        }
        // ---- Lagrange phase, cells g-1 .. g+n
        for (int i = g - 1; i <= g + n; ++i) {
          const std::size_t si = static_cast<std::size_t>(i), fr = si + 1;
          const double V = P.vol[si];
          const double Vl = V + P.dvol[fr] - P.dvol[si];
          P.vlag[si] = Vl;
          double m = 0.0, ie = 0.0;
          for (int k = 0; k < M; ++k) {
            const std::size_t ki = static_cast<std::size_t>(k * N + i);
            P.mk[ki] = P.a[ki] * P.r[ki] * V;
            P.iek[ki] = P.mk[ki] * P.e[ki];
            m += P.mk[ki];
            ie += P.iek[ki];
          }
          P.mass[si] = m;
          const double Al = P.area[si], Ar = P.area[fr];
          double ke0 = 0.0, ke1 = 0.0;
          double E = 0.0;
          for (std::size_t q = 0; q < 3; ++q) ke0 += 0.5 * m * P.u[q][si] * P.u[q][si];
          E = ie + ke0 - dt * (Ar * P.pstar[fr] * P.ustar[fr] - Al * P.pstar[si] * P.ustar[si]);
          // normal momentum: faces, hoop stress (axisymmetric r), gravity
          double mn = m * un[si] - dt * (Ar * P.pstar[fr] - Al * P.pstar[si]) + dt * (Ar - Al) * P.hoop[si] * (radial ? 1.0 : 0.0);
          const double mn_g = mn + dt * m * grav;
          E += dt * grav * 0.5 * (mn + mn_g);
          mn = mn_g;
          P.mom[static_cast<std::size_t>(d)][si] = mn;
          // transverse momentum from the shear tractions
          for (int tt = 0; tt < 2; ++tt) {
            const std::size_t comp = static_cast<std::size_t>(tt == 0 ? t1 : t2);
            const auto& sh = P.shear[static_cast<std::size_t>(tt)];
            const auto& ut = P.u[comp];
            double tr = 0.5 * (sh[si] + sh[si + 1]), tl = 0.5 * (sh[si - 1] + sh[si]);
            if (has_body) {   // free slip on the body: no shear traction
              if (P.solid[si] | P.solid[si + 1]) tr = 0.0;
              if (P.solid[si - 1] | P.solid[si]) tl = 0.0;
            }
            const double ur = 0.5 * (ut[si] + ut[si + 1]), ul = 0.5 * (ut[si - 1] + ut[si]);
            P.mom[comp][si] = m * ut[si] + dt * (Ar * tr - Al * tl);
            E += dt * (Ar * tr * ur - Al * tl * ul);
            if (has_body && friction > 0.0 && !P.solid[si] && (P.solid[si - 1] | P.solid[si + 1])) {
              // Coulomb friction on the body's face: mu times the compressive normal stress,
              // opposing the sliding, never reversing it within a step. The kinetic energy it
              // removes stays in the cell's total energy, i.e. becomes heat.
              const double pn = std::max(P.solid[si + 1] ? P.pstar[fr] : 0.0, 0.0) * Ar +
                                std::max(P.solid[si - 1] ? P.pstar[si] : 0.0, 0.0) * Al;
              const double slide = P.mom[comp][si] - m * body_velocity_[comp];
              const double cut = std::min(friction * pn * dt, std::abs(slide));
              P.mom[comp][si] -= std::copysign(cut, slide);
            }
          }
          const double inv_m = 1.0 / m;
          for (std::size_t q = 0; q < 3; ++q) ke1 += 0.5 * P.mom[q][si] * P.mom[q][si] * inv_m;
          P.ke[si] = ke1;
          const double die = E - ke1 - ie;
          const double dV = Vl - V;
          // share the volume change and the work among the materials
          int present = 0;
          double wsum = 0.0, dv_frag = 0.0;
          for (int k = 0; k < M; ++k) {
            const std::size_t ki = static_cast<std::size_t>(k * N + i);
            if (P.a[ki] > kAlphaMin) {
              ++present;
              wsum += P.a[ki] / std::max(P.kk[ki], 1.0);
            } else {
              dv_frag += P.a[ki] * dV;
            }
          }
          if (present <= 1) {
            for (int k = 0; k < M; ++k) {
              const std::size_t ki = static_cast<std::size_t>(k * N + i);
              P.vk[ki] = P.a[ki] * Vl;
              if (P.a[ki] > kAlphaMin) P.iek[ki] += die;
            }
          } else {
            double work = 0.0;
            for (int k = 0; k < M; ++k) {
              const std::size_t ki = static_cast<std::size_t>(k * N + i);
              double dvk = P.a[ki] * dV;
              if (P.a[ki] > kAlphaMin) dvk = (dV - dv_frag) * (P.a[ki] / std::max(P.kk[ki], 1.0)) / wsum;
              P.vk[ki] = P.a[ki] * V + dvk;
              if (P.vk[ki] < 0.05 * P.a[ki] * V) P.vk[ki] = 0.05 * P.a[ki] * V;   // no material collapses in one step
              if (P.a[ki] > kAlphaMin) {
                const double wk = -P.pk[ki] * dvk;
                P.iek[ki] += wk;
                work += wk;
              }
            }
            // Pressure relaxation: materials at unequal pressures exchange volume towards the
            // common pressure p_eq of the linearised mixture (at most half a material's volume per
            // step). Each material works at its own pressure; the dissipated remainder is shared
            // as heat by mass, so a rarefied sliver squeezed by products is not heated without
            // bound and total energy is conserved.
            double sw = 0.0, swp = 0.0;
            for (int k = 0; k < M; ++k) {
              const std::size_t ki = static_cast<std::size_t>(k * N + i);
              if (P.a[ki] <= kAlphaMin) continue;
              const double wk = P.a[ki] / std::max(P.kk[ki], 1.0);
              sw += wk;
              swp += wk * P.pk[ki];
            }
            const double p_eq = swp / sw;
            double theta = 1.0;
            for (int k = 0; k < M; ++k) {
              const std::size_t ki = static_cast<std::size_t>(k * N + i);
              if (P.a[ki] <= kAlphaMin) continue;
              const double dk = P.a[ki] * Vl * (P.pk[ki] - p_eq) / std::max(P.kk[ki], 1.0);
              if (dk < 0.0) theta = std::min(theta, 0.5 * P.vk[ki] / -dk);
              if (dk > 0.0) theta = std::min(theta, P.vk[ki] / dk);   // at most double in a step
            }
            double relax_heat = 0.0;
            for (int k = 0; k < M; ++k) {
              const std::size_t ki = static_cast<std::size_t>(k * N + i);
              if (P.a[ki] <= kAlphaMin) continue;
              const double kk = std::max(P.kk[ki], 1.0);
              const double dk = theta * P.a[ki] * Vl * (P.pk[ki] - p_eq) / kk;
              // each material works at its own pressure (not a linearised average: that heats a
              // squeezed sliver of air without bound)...
              const double w_relax = P.pk[ki] * dk;
              P.vk[ki] += dk;
              P.iek[ki] -= w_relax;
              relax_heat += w_relax;   // ...and the irreversible remainder is heat
            }
            for (int k = 0; k < M; ++k) {
              const std::size_t ki = static_cast<std::size_t>(k * N + i);
              if (P.a[ki] > kAlphaMin) P.iek[ki] += relax_heat * P.mk[ki] / m;
            }
            // keep the material volumes summing to the cell's
            double vs = 0.0;
            for (int k = 0; k < M; ++k) vs += P.vk[static_cast<std::size_t>(k * N + i)];
            for (int k = 0; k < M; ++k) P.vk[static_cast<std::size_t>(k * N + i)] *= Vl / vs;
            const double rest = die - work;   // dissipation and stress work: heat shared by mass
            double iesum = 0.0;
            for (int k = 0; k < M; ++k) iesum += std::max(P.iek[static_cast<std::size_t>(k * N + i)], 0.0);
            for (int k = 0; k < M; ++k) {
              const std::size_t ki = static_cast<std::size_t>(k * N + i);
              if (P.a[ki] <= kAlphaMin) continue;
              const double share = (rest >= 0.0 || iesum <= 0.0) ? P.mk[ki] / m : std::max(P.iek[ki], 0.0) / iesum;
              P.iek[ki] += rest * share;
            }
          }
        }
        // ---- remap: fluxes through faces g .. g+n
        for (int f = g; f <= g + n; ++f) {
          const std::size_t sf = static_cast<std::size_t>(f);
          const double dvf = P.dvol[sf];
          for (int k = 0; k < M; ++k) {
            const std::size_t kf = static_cast<std::size_t>(k * (N + 1) + f);
            P.fv[kf] = P.fm[kf] = P.fe[kf] = P.fh[kf] = P.fa[kf] = 0.0;
            for (auto& fs : P.fs) fs[kf] = 0.0;
          }
          for (auto& fm : P.fmom) fm[sf] = 0.0;
          P.fke[sf] = 0.0;
          if (dvf == 0.0) continue;
          const bool out_high = dvf > 0.0;
          const int D = out_high ? f - 1 : f;
          const std::size_t sD = static_cast<std::size_t>(D);
          const double sign = out_high ? 1.0 : -1.0;
          const double vD = P.vlag[sD];
          const double bfrac = std::min(std::abs(dvf) / vD, 1.0);
          const double offset = sign * 0.5 * line_w[sD] * (1.0 - bfrac);
          // material volumes
          double raw_sum = 0.0;
          double raw[8];
          for (int k = 0; k < M && k < 8; ++k) {
            const std::size_t kD = static_cast<std::size_t>(k * N + D);
            const double al = P.vk[kD] / vD;
            const double wl = P.wl[kD];
            raw[k] = M == 1 ? bfrac : wl * thincOutflow(al, P.a[kD - 1], P.a[kD + 1], bfrac, out_high, beta) + (1.0 - wl) * al * bfrac;
            raw_sum += raw[k];
          }
          const double target = std::abs(dvf);
          double dvk[8];
          double excess = 0.0, room = 0.0;
          for (int k = 0; k < M; ++k) {
            const std::size_t kD = static_cast<std::size_t>(k * N + D);
            dvk[k] = raw_sum > 0.0 ? raw[k] / raw_sum * target : target / M;
            if (dvk[k] > P.vk[kD]) {
              excess += dvk[k] - P.vk[kD];
              dvk[k] = P.vk[kD];
            } else {
              room += P.vk[kD] - dvk[k];
            }
          }
          if (excess > 0.0 && room > 0.0)
            for (int k = 0; k < M; ++k) {
              const std::size_t kD = static_cast<std::size_t>(k * N + D);
              if (dvk[k] < P.vk[kD]) dvk[k] += excess * (P.vk[kD] - dvk[k]) / room;
            }
          double dm = 0.0;
          for (int k = 0; k < M; ++k) {
            const std::size_t kD = static_cast<std::size_t>(k * N + D), kf = static_cast<std::size_t>(k * (N + 1) + f);
            if (dvk[k] <= 0.0 || P.mk[kD] <= 0.0) continue;
            double mflux, eflux;
            if (dvk[k] >= P.vk[kD] * (1.0 - 1e-13)) {
              mflux = P.mk[kD];
              eflux = P.iek[kD];
            } else {
              double rho_f = P.mk[kD] / P.vk[kD], e_f = P.iek[kD] / P.mk[kD];
              if (second && P.a[kD - 1] > kPureCell && P.a[kD] > kPureCell && P.a[kD + 1] > kPureCell) {
                // A slope may not push what stays in the donor outside the donor's own range: its
                // effect is scaled down when more than half the donor leaves.
                const double il = line_inv[sD], ir = line_inv[sD + 1];
                const double keep = std::min(1.0, (P.vk[kD] - dvk[k]) / dvk[k]);
                rho_f += keep * offset * vanLeer((P.r[kD] - P.r[kD - 1]) * il, (P.r[kD + 1] - P.r[kD]) * ir);
                e_f += keep * offset * vanLeer((P.e[kD] - P.e[kD - 1]) * il, (P.e[kD + 1] - P.e[kD]) * ir);
              }
              mflux = std::min(rho_f * dvk[k], P.mk[kD]);
              eflux = mflux * e_f;
            }
            P.fv[kf] = sign * dvk[k];
            P.fm[kf] = sign * mflux;
            P.fe[kf] = sign * eflux;
            P.fh[kf] = sign * mflux * P.h[kD];
            P.fa[kf] = sign * mflux * P.ad[kD];
            if (!fields_[static_cast<std::size_t>(k)].s[0].empty())
              for (std::size_t q = 0; q < 6; ++q) P.fs[q][kf] = sign * mflux * P.s[q][kD];
            dm += mflux;
          }
          double ke = 0.0;
          const double keep_m = dm > 0.0 ? std::clamp((P.mass[sD] - dm) / dm, 0.0, 1.0) : 1.0;
          for (std::size_t q = 0; q < 3; ++q) {
            const auto& uq = P.u[q];
            double uf = P.mom[q][sD] / P.mass[sD];
            if (second) {
              uf += keep_m * offset * vanLeer((uq[sD] - uq[sD - 1]) * line_inv[sD], (uq[sD + 1] - uq[sD]) * line_inv[sD + 1]);
            }
            P.fmom[q][sf] = sign * dm * uf;
            ke += 0.5 * dm * uf * uf;
          }
          P.fke[sf] = sign * ke;
        }
        // ---- new Eulerian state of cells g .. g+n-1, scattered back
        double sink = 0.0;
        for (int i = g; i < g + n; ++i) {
          const std::size_t si = static_cast<std::size_t>(i), c = cell(i);
          if (has_body && P.solid[si]) continue;   // the body's cells keep their (unused) state
          double m = 0.0, vs = 0.0;
          double mk_new[8], vk_new[8], ie_new[8];
          for (int k = 0; k < M; ++k) {
            const std::size_t ki = static_cast<std::size_t>(k * N + i), kf = static_cast<std::size_t>(k * (N + 1) + i);
            vk_new[k] = P.vk[ki] + P.fv[kf] - P.fv[kf + 1];
            mk_new[k] = P.mk[ki] + P.fm[kf] - P.fm[kf + 1];
            ie_new[k] = P.iek[ki] + P.fe[kf] - P.fe[kf + 1];
            if (mk_new[k] <= 0.0) {
              mk_new[k] = 0.0;
              vk_new[k] = 0.0;
              ie_new[k] = 0.0;
            } else if (vk_new[k] <= 0.0) {
              vk_new[k] = mk_new[k] / std::max(P.r[ki], 1e-30);   // a sliver: keep its mass
            }
            m += mk_new[k];
            vs += vk_new[k];
          }
          double mom[3], ke_new = 0.0;
          for (std::size_t q = 0; q < 3; ++q) {
            mom[q] = P.mom[q][si] + P.fmom[q][si] - P.fmom[q][si + 1];
            ke_new += 0.5 * mom[q] * mom[q] / m;
          }
          const double ke_remap = P.ke[si] + P.fke[si] - P.fke[si + 1];
          const double heat = ke_remap - ke_new;   // what the remap took from the flow
          const double V = P.vol[si];
          bool ok = m > 0.0 && std::isfinite(m);
          for (int k = 0; k < M; ++k) {
            auto& F = fields_[static_cast<std::size_t>(k)];
            const std::size_t ki = static_cast<std::size_t>(k * N + i), kf = static_cast<std::size_t>(k * (N + 1) + i);
            if (mk_new[k] <= 0.0) {
              F.alpha[c] = 0.0;
              F.e[c] = 0.0;
              F.h0[c] = 0.0;
              if (!F.s[0].empty())
                for (auto& sc : F.s) sc[c] = 0.0;
              continue;
            }
            const double al = vk_new[k] / vs;
            F.alpha[c] = al;
            F.rho[c] = mk_new[k] / (al * V);
            F.e[c] = (ie_new[k] + heat * mk_new[k] / m) / mk_new[k];
            F.h0[c] = (P.h[ki] * P.mk[ki] + P.fh[kf] - P.fh[kf + 1]) / mk_new[k];
            if (!F.s[0].empty())
              for (std::size_t q = 0; q < 6; ++q) F.s[q][c] = (P.s[q][ki] * P.mk[ki] + P.fs[q][kf] - P.fs[q][kf + 1]) / mk_new[k];
            if (!F.adiabat.empty()) {
              // the products' adiabat (SolverOptions::products_adiabat): carried with the mass; a
              // compressing sweep may raise it; in an expanding one the products follow it (the
              // energy off it, mostly the scheme's heat, goes to the sink)
              // (a mass-weighted mean of the cell and its donors, kept within their range: a
              // sliver's mass may nearly cancel while its fluxes' adiabats do not)
              const double lo = std::min({P.ad[ki - 1], P.ad[ki], P.ad[ki + 1]}), hi = std::max({P.ad[ki - 1], P.ad[ki], P.ad[ki + 1]});
              const double carried = std::clamp((P.ad[ki] * P.mk[ki] + P.fa[kf] - P.fa[kf + 1]) / mk_new[k], lo, hi);
              const auto& jw = mats_[static_cast<std::size_t>(k)].jwl;
              const double Vr = jw.rho0 / F.rho[c];
              if (F.h0[c] >= 1.0 && al > kAdiabatMinAlpha && materials::JwlIsentrope::covers(Vr)) {
                const double vw = std::pow(Vr, jw.omega);
                const double e_s = isentropes_[static_cast<std::size_t>(k)]->energy(Vr) / jw.rho0;
                // Entropy never falls below the CJ isentrope's (c >= 0): all products start there
                // and physics only raises it; this also keeps their energy above e_s(V) > 0.
                const double c_now = (F.e[c] - e_s) * vw;
                const double c_new = P.vlag[si] < P.vol[si] ? std::max(c_now, 0.0) : std::max(carried, 0.0);
                if (c_new != c_now) {
                  const double e_adiabat = e_s + c_new / vw;
                  sink += mk_new[k] * (F.e[c] - e_adiabat);
                  F.e[c] = e_adiabat;
                }
                F.adiabat[c] = c_new;
              } else {
                // still burning (the CJ isentrope's, 0), or a sliver squeezed or rarefied off the
                // table, whose energy is left to the scheme
                F.adiabat[c] = carried;
              }
            }
            ok = ok && std::isfinite(F.rho[c]) && F.rho[c] > 0.0 && std::isfinite(F.e[c]);
          }
          for (std::size_t q = 0; q < 3; ++q) {
            u_[q][c] = mom[q] / m;
            ok = ok && std::isfinite(u_[q][c]);
          }
          if (!ok && c < my_bad) my_bad = c;
        }
        if (track) pencil_sink[static_cast<std::size_t>(a) * static_cast<std::size_t>(n2) + static_cast<std::size_t>(b)] = sink;
      }
#pragma omp critical
    bad_cell = std::min(bad_cell, my_bad);
  }
  for (const double e : pencil_sink) adiabat_sink_ += e;   // in pencil order: thread-count independent
  if (has_body) {
    for (std::size_t pc = 0; pc < pencil_impulse.size() / static_cast<std::size_t>(M); ++pc)
      for (int k = 0; k < M; ++k) {
        const double imp = pencil_impulse[pc * static_cast<std::size_t>(M) + static_cast<std::size_t>(k)];
        body_impulse_[static_cast<std::size_t>(d)] += imp;
        body_impulse_mat_[static_cast<std::size_t>(k)][static_cast<std::size_t>(d)] += imp;
      }
  }
  if (bad_cell != std::numeric_limits<std::size_t>::max()) checkCell(bad_cell, d == 0 ? "sweep along axis 0" : (d == 1 ? "sweep along axis 1" : "sweep along axis 2"));
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
                             what, ix.i, ix.j, ix.k, grid_.centre(0, ix.i), grid_.centre(1, ix.j), grid_.centre(2, ix.k), mat,
                             time_, step_, stage));
}

// ------------------------------------------------------------------------------------------------

void Solver::step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw RunError(fmt::format("invalid time step {:g} s at t = {:.6g} s", dt, time_));
  body_impulse_ = Vec3{};
  for (auto& v : body_impulse_mat_) v = Vec3{};
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

void Solver::advanceTo(double t_end, const std::function<void(const Solver&)>& on_step) {
  const auto t0 = std::chrono::steady_clock::now();
  while (time_ < t_end * (1.0 - 1e-14)) {
    double dt = stableTimeStep();
    if (last_dt_ > 0.0) dt = std::min(dt, 1.2 * last_dt_);
    else dt *= opt_.initial_dt_fraction;
    dt = std::min({dt, opt_.max_dt, t_end - time_});
    if (!(dt >= opt_.min_dt) && t_end - time_ > opt_.min_dt) {
      // name the cell that forces the step down
      throw RunError(fmt::format("time step collapsed to {:g} s (limit {:g} s) at t = {:.6g} s, step {}; {}", dt, opt_.min_dt, time_, step_,
                                 describeLimitingCell()));
    }
    step(dt);
    if (on_step) on_step(*this);
  }
  stats_.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace ejecta::hydro
