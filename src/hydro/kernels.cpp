// The sweep's kernels on one pencil (pencil.hpp): slopes, faces, Lagrange phase with the
// mixed-cell closure, remap fluxes. Each is a plain loop over the pencil; the solver owns gather,
// scatter and the loop over pencils.
#include "hydro/pencil.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "mesh/grid.hpp"

namespace ejecta::hydro {

using mesh::kGhost;

namespace {
// van Leer's limiter, 2ab / (a + b) where a and b share a sign, else 0; written with selects
// around a division that cannot trap, so that a loop of them vectorises (the same number).
inline double vanLeer(double a, double b) {
  const bool same_sign = a * b > 0.0;
  const double num = 2.0 * a * b, den = a + b;
  return (same_sign ? num : 0.0) / (same_sign ? den : 1.0);
}

inline bool anySolid(const Pencil& P) {
  for (const unsigned char x : P.solid)
    if (x) return true;
  return false;
}

}  // namespace

void Pencil::resize(int cells, int materials) {
  n = cells;
  N = cells + 2 * kGhost;
  M = materials;
  for (int k = 0; k < kMaxMaterials; ++k) {
    mat[k] = k;
    strengthless[k] = false;
  }
  const auto sN = static_cast<std::size_t>(N), sF = sN + 1, sMN = sN * static_cast<std::size_t>(M),
             sMF = sF * static_cast<std::size_t>(M);
  for (auto* v : {&vol, &rho, &P, &K, &Kp, &Z, &zs, &zmax, &soft, &p_per_k, &hoop, &dil, &pmin, &vlag, &mass, &ke, &su, &sp, &ie_cell, &die, &w_grav, &present, &sum_snn, &sum_s11}) v->assign(sN, 0.0);
  for (auto* v : {&area, &ustar, &pstar, &dvol}) v->assign(sF, 0.0);
  for (auto& v : u) v.assign(sN, 0.0);
  for (auto& v : mom) v.assign(sN, 0.0);
  for (auto& v : shear) v.assign(sN, 0.0);
  for (auto& v : fmom) v.assign(sF, 0.0);
  for (auto* v : {&a, &r, &e, &h, &pk, &kk, &wl, &tlo, &thi, &vk, &mk, &iek}) v->assign(sMN, 0.0);
  for (auto& v : s) v.assign(sMN, 0.0);
  for (auto* v : {&fv, &fm, &fe, &fh, &fkek}) v->assign(sMF, 0.0);
  for (auto& v : fs) v.assign(sMF, 0.0);
  solid.assign(sN, 0);
}

double thincOutflow(double a, double a_lo, double a_hi, double b, bool out_high, double beta) {
  return thincOutflow(a, a_lo, a_hi, b, out_high, ThincProfile(beta));
}

double thincOutflow(double a, double a_lo, double a_hi, double b, bool out_high, const ThincProfile& th) {
  ThincFace face(b, out_high, th);
  return thincOutflow(a, a_lo, a_hi, face);
}

// Whether the cell holds a THINC profile (its fraction strictly inside (1e-6, 1 - 1e-6) and
// bracketed by its neighbours) and, if so, its direction gamma = +-1 and t = exp(2 beta xc), xc the
// profile's centre, from the mean: exp(2 beta gamma (a - 1/2)) = (e^beta + e^-beta t) / (1 + t).
static bool thincCentre(double a, double a_lo, double a_hi, const ThincProfile& th, double& gamma, double& t) {
  if (a < 1e-6 || a > 1.0 - 1e-6 || (a_hi - a) * (a - a_lo) <= 0.0) return false;
  gamma = a_hi > a_lo ? 1.0 : -1.0;
  const double eq = std::exp(2.0 * th.beta * gamma * (a - 0.5));   // gamma = +-1, so 1/gamma = gamma
  t = (th.exp_beta - eq) / (eq - th.exp_minus_beta);
  return true;
}

double thincOutflow(double a, double a_lo, double a_hi, ThincFace& face) {
  const double b = face.b;
  const double hi_cap = std::min(a, b), lo_cap = std::max(0.0, a - (1.0 - b));
  // Within the caps, the upper one winning: at a = 1 the lower cap 1 - (1 - b) can round one ulp
  // above b, where std::clamp's precondition (lo <= hi) fails; this is what libstdc++'s clamp
  // computes, without the precondition.
  const auto capped = [&](double x) { return std::min(std::max(x, lo_cap), hi_cap); };
  const ThincProfile& th = face.th;   // the face's own copy
  double gamma = 0.0, t = 0.0;
  // No interface to sharpen where the neighbours do not bracket the cell: the donor mean.
  if (!thincCentre(a, a_lo, a_hi, th, gamma, t)) return capped(a * b);
  const double beta = th.beta;
  // The flux is the integral of the tanh profile, a difference of two ln cosh; that difference is
  // the log of a ratio of cosh, which in t is a ratio of two sums of positive terms: one log here,
  // and one exp per face shared by its materials, where the two ln cosh took four calls and the
  // centre's log one more. (Both forms carry about 1e-16 of absolute error, which at swept
  // fractions under 1e-8 is most of a tiny flux.)
  const double ef = face.exponential();
  const double ratio = face.out_high ? (th.exp_beta + t * th.exp_minus_beta) / (ef + t / ef) : (ef + t / ef) / (1.0 + t);
  return capped(0.5 * b + gamma / (2.0 * beta) * std::log(ratio));
}

void shareHeat(int M, const double* mass, const double* loss, double heat, const double* held, double* add) {
  double m = 0.0, given = 0.0;
  for (int k = 0; k < M; ++k) m += mass[k];
  if (heat >= 0.0) {
    for (int k = 0; k < M; ++k) {
      add[k] = m > 0.0 ? std::min(std::max(loss[k], 0.0), 2.0 * heat * mass[k] / m) : 0.0;
      given += add[k];
    }
  } else {   // a net gain of kinetic energy (limited slopes): taken from the internal energy held
    double pos = 0.0;
    for (int k = 0; k < M; ++k) pos += std::max(held[k], 0.0);
    for (int k = 0; k < M; ++k) {
      add[k] = pos > 0.0 ? heat * std::max(held[k], 0.0) / pos : 0.0;
      given += add[k];
    }
  }
  if (m > 0.0)
    for (int k = 0; k < M; ++k) add[k] += (heat - given) * mass[k] / m;
}

void foldFragments(int M, double cut, double vs, double* vk, double* mk, double* ie, double* folded) {
  double fold_v = 0.0, fold_m = 0.0, fold_e = 0.0, keep_v = 0.0;
  int kept = 0;
  for (int k = 0; k < M; ++k) {
    folded[k] = 0.0;
    if (mk[k] <= 0.0) continue;
    if (vk[k] < cut * vs) {
      fold_v += vk[k];
      fold_m += mk[k];
      fold_e += ie[k];
      folded[k] = mk[k];
      mk[k] = vk[k] = ie[k] = 0.0;
    } else {
      keep_v += vk[k];
      ++kept;
    }
  }
  if (!(fold_v > 0.0)) return;
  // keep_v > 0: the largest material holds at least vs / M, far above the cut
  for (int k = 0; k < M; ++k) {
    if (mk[k] <= 0.0) continue;
    const double w = vk[k] / keep_v, before = mk[k];
    vk[k] = kept == 1 ? vs : vk[k] + w * fold_v;   // one left: its fraction exactly 1
    mk[k] += w * fold_m;
    folded[k] = -(mk[k] - before);   // what it took, exactly
    ie[k] += w * fold_e;
  }
}

// ------------------------------------------------------------------------------------------------

void nearWallShares(const Pencil& P, const SweepSetup& S, int from, int step, double depth, double* share) {
  const int M = P.M, lo = kGhost, hi = kGhost + P.n;
  double total = 0.0, left = depth;
  for (int k = 0; k < M; ++k) share[k] = 0.0;
  for (int i = from; i >= lo && i < hi && !P.solid[static_cast<std::size_t>(i)]; i += step) {
    const std::size_t si = static_cast<std::size_t>(i);
    const double part = i == from ? 1.0 : std::min(1.0, left / S.width[si]);
    if (!(part > 0.0)) break;
    const double v = P.vol[si] * part;
    for (int k = 0; k < M; ++k) share[k] += P.a[P.at(k, i)] * v;
    total += v;
    left -= S.width[si];
  }
  if (total > 0.0) {
    for (int k = 0; k < M; ++k) share[k] /= total;
  } else {   // a ghost cell beside the face (the boundary's): the cell's own fractions
    for (int k = 0; k < M; ++k) share[k] = P.a[P.at(k, from)];
  }
}

// Books one load increment: `total` (N s along `comp`) and its split by the pencil's materials,
// beside the face (`by_mat`) and within each of kNearWallDepth_m (`near`).
static void bookLoad(const Pencil& P, const SweepSetup& S, std::size_t comp, double total, const double* by_mat,
                     const double (*near)[kMaxMaterials], PencilLedger& ledger) {
  const int M = P.M;
  // booked by the run's material index (the pencil may carry only some of the run's materials)
  ledger.impulse_total[comp] += total;
  for (int k = 0; k < M; ++k) {
    const int q = P.mat[k];
    ledger.impulse_on_body[q][comp] += by_mat[k];
    for (int l = 0; l < kNearWallDepths; ++l) ledger.impulse_near_body[l][q][comp] += near[l][k];
  }
  if (ledger.events) {   // [key, component, total, by material (the run's M), near the wall (3 x the run's M)]
    int Mr = S.materials;   // 0 where the caller did not say: at least every material the pencil names
    for (int k = 0; k < M; ++k) Mr = std::max(Mr, P.mat[k] + 1);
    double row[kMaxMaterials], near_row[kNearWallDepths][kMaxMaterials];
    for (int q = 0; q < Mr; ++q) {
      row[q] = 0.0;
      for (int l = 0; l < kNearWallDepths; ++l) near_row[l][q] = 0.0;
    }
    for (int k = 0; k < M; ++k) {
      row[P.mat[k]] = by_mat[k];
      for (int l = 0; l < kNearWallDepths; ++l) near_row[l][P.mat[k]] = near[l][k];
    }
    auto& e = *ledger.events;
    e.push_back(ledger.key);
    e.push_back(static_cast<double>(comp));
    e.push_back(total);
    for (int q = 0; q < Mr; ++q) e.push_back(row[q]);
    for (int l = 0; l < kNearWallDepths; ++l)
      for (int q = 0; q < Mr; ++q) e.push_back(near_row[l][q]);
  }
}

// Books a normal load on the body at the face beside fluid cell `fluid`, the body lying `step` = -1
// (below) or +1 (above) along the pencil: `total` (N s along `comp`, into impulse_total) and `imp`
// (the same against the reference pressure) by the material in the cell and by the materials within
// each of kNearWallDepth_m; `cell_only`: the cell's own fractions at every depth.
static void bookLoadByMaterial(const Pencil& P, const SweepSetup& S, int fluid, int step, std::size_t comp, double total, double imp,
                               bool cell_only, PencilLedger& ledger) {
  const int M = P.M;
  double by_mat[kMaxMaterials], near[kNearWallDepths][kMaxMaterials];
  for (int k = 0; k < M; ++k) by_mat[k] = imp * P.a[P.at(k, fluid)];
  double share[kMaxMaterials];
  for (int l = 0; l < kNearWallDepths; ++l) {
    if (cell_only) {
      for (int k = 0; k < M; ++k) near[l][k] = by_mat[k];
      continue;
    }
    nearWallShares(P, S, fluid, -step, kNearWallDepth_m[static_cast<std::size_t>(l)], share);
    for (int k = 0; k < M; ++k) near[l][k] = imp * share[k];
  }
  bookLoad(P, S, comp, total, by_mat, near, ledger);
}

// Books the friction `taken` (N s along `comp`) at the face beside cell `cell`: all of it to the
// materials with strength there, by their volume (`held`, their fractions' sum, frictionGrip), at
// every depth: friction is a traction at the face, not a layer's.
static void bookFriction(const Pencil& P, const SweepSetup& S, int cell, std::size_t comp, double taken, double held, PencilLedger& ledger) {
  const int M = P.M;
  double by_mat[kMaxMaterials], near[kNearWallDepths][kMaxMaterials];
  for (int k = 0; k < M; ++k) by_mat[k] = P.strengthless[k] ? 0.0 : taken * (P.a[P.at(k, cell)] / held);
  for (int l = 0; l < kNearWallDepths; ++l)
    for (int k = 0; k < M; ++k) near[l][k] = by_mat[k];
  bookLoad(P, S, comp, taken, by_mat, near, ledger);
}

// The share of a contact at a face of cell `cell` held by materials that carry a shear stress (sand):
// the sum of their volume fractions (the caller caps it at 1). A gas, the products or water carries
// no shear stress in this model and cannot transmit a tangential traction to the plate, so a
// Coulomb coefficient measured for soil on steel does not apply to it.
static double frictionGrip(const Pencil& P, int cell) {
  double grip = 0.0;
  for (int k = 0; k < P.M; ++k)
    if (!P.strengthless[k]) grip += P.a[P.at(k, cell)];
  return grip;
}

// van Leer-limited slopes of u and p in cells 1 .. N-2 (computeSlopes): restrict-qualified, so that
// the loop vectorises.
[[gnu::noinline]] static void limitedSlopes(std::ptrdiff_t N, const double* __restrict inv_dx, const double* __restrict un, const double* __restrict p,
                                            double* __restrict su, double* __restrict sp) {
  for (std::ptrdiff_t i = 1; i < N - 1; ++i) {
    const double il = inv_dx[i], ir = inv_dx[i + 1];
    su[i] = vanLeer((un[i] - un[i - 1]) * il, (un[i + 1] - un[i]) * ir);
    sp[i] = vanLeer((p[i] - p[i - 1]) * il, (p[i + 1] - p[i]) * ir);
  }
}

// An r-sweep's dilatation rate (Pencil::dil): the velocity slope plus geo u / r (geo 1
// axisymmetric, 2 spherical; a cell centre is never on the axis). A ghost cell beyond the domain's
// boundary takes the geometric part of the interior cell whose state it holds: a reflecting wall's
// ghost holds its mirror's velocity reversed, and its own -u / r would make the two states of the
// wall's face differ and move the wall (on the axis the two are equal); an outflow side's ghosts
// copy the boundary cell.
static void dilatationRates(const Pencil& P, const SweepSetup& S, double* dil) {
  const int N = P.N, g = kGhost, n = P.n;
  const double* su = P.su.data();
  const double geo = P.spherical ? 2.0 : 1.0;
  const double* un = P.u[static_cast<std::size_t>(S.d)].data();
  for (int i = 1; i < N - 1; ++i) {
    int m = i;
    if (i < g && S.lo_is_boundary) m = S.lo_ghosts_copy ? g : std::min(2 * g - 1 - i, g + n - 1);
    if (i >= g + n && S.hi_is_boundary) m = S.hi_ghosts_copy ? g + n - 1 : std::max(2 * (g + n) - 1 - i, g);
    dil[i] = su[i] + geo * un[m] / S.xc[m];
  }
}

void computeSlopes(Pencil& P, const SweepSetup& S) {
  const int N = P.N;
  if (!S.second_order) {
    for (int i = 1; i < N - 1; ++i) P.su[static_cast<std::size_t>(i)] = P.sp[static_cast<std::size_t>(i)] = P.dil[static_cast<std::size_t>(i)] = 0.0;
    return;
  }
  limitedSlopes(N, S.inv_dx, P.u[static_cast<std::size_t>(S.d)].data(), P.P.data(), P.su.data(), P.sp.data());
  if (P.radial) dilatationRates(P, S, P.dil.data());
  if (!anySolid(P)) return;
  for (int i = 1; i < N - 1; ++i) {   // first order beside the body: no slope, no half step
    const std::size_t si = static_cast<std::size_t>(i);
    if (P.solid[si - 1] | P.solid[si] | P.solid[si + 1]) P.su[si] = P.sp[si] = P.dil[si] = 0.0;
  }
}

namespace {
// The MUSCL-Hancock states on the two sides of the face between cells L and R: velocity and
// normal stress extrapolated by half a cell and advanced by half a step (the stress with the
// predictor's stiffness Kp and the cell's dilatation rate dil).
struct FaceStates {
  double uL, pL, uR, pR;
};
inline FaceStates hancockStates(std::ptrdiff_t L, std::ptrdiff_t R, double dt, const double* width, const double* un, const double* su,
                                const double* sp, const double* rho, const double* p, const double* Kp, const double* dil) {
  const double hl = 0.5 * width[L], hr = 0.5 * width[R];
  return {un[L] + hl * su[L] - 0.5 * dt * sp[L] / rho[L], p[L] + hl * sp[L] - 0.5 * dt * Kp[L] * dil[L],
          un[R] - hr * su[R] - 0.5 * dt * sp[R] / rho[R], p[R] - hr * sp[R] - 0.5 * dt * Kp[R] * dil[R]};
}
}  // namespace

// The acoustic Riemann problem at faces f0 .. f1 (solveFaces): a plain loop over restrict-qualified
// arrays, so that it vectorises.
[[gnu::noinline]] static void acousticFaces(std::ptrdiff_t f0, std::ptrdiff_t f1, double dt, const double* __restrict width, const double* __restrict un,
                                            const double* __restrict su, const double* __restrict sp, const double* __restrict rho, const double* __restrict p,
                                            const double* __restrict Kp, const double* __restrict dil, const double* __restrict Z, double* __restrict ustar,
                                            double* __restrict pstar) {
  for (std::ptrdiff_t f = f0; f <= f1; ++f) {
    const auto [uL, pL, uR, pR] = hancockStates(f - 1, f, dt, width, un, su, sp, rho, p, Kp, dil);
    const double zl = Z[f - 1], zr = Z[f];
    const double zs = zl + zr;
    ustar[f] = (zl * uL + zr * uR + pL - pR) / zs;
    pstar[f] = (zr * pL + zl * pR + zl * zr * (uL - uR)) / zs;
  }
}

// The same with a mixed cell's shock impedance (mixture_reuss): a side that is compressed by
// du = its velocity's change to the face's answers with Z + zs du (zs = rho / alpha_soft, the
// snow-plough shock of its soft fraction; 0 in a cell of one material), at most the frozen sum's
// impedance (zmax; the step is capped alike). Each side's du is its own share of the jump, from the
// acoustic solution, then the problem is solved again with it.
[[gnu::noinline]] static void shockFaces(std::ptrdiff_t f0, std::ptrdiff_t f1, double dt, const double* __restrict width, const double* __restrict un,
                                         const double* __restrict su, const double* __restrict sp, const double* __restrict rho, const double* __restrict p,
                                         const double* __restrict Kp, const double* __restrict dil, const double* __restrict Z, const double* __restrict ZS,
                                         const double* __restrict ZMAX, double* __restrict ustar, double* __restrict pstar) {
  for (std::ptrdiff_t f = f0; f <= f1; ++f) {
    const auto [uL, pL, uR, pR] = hancockStates(f - 1, f, dt, width, un, su, sp, rho, p, Kp, dil);
    const double zl0 = Z[f - 1], zr0 = Z[f];
    const double u0 = (zl0 * uL + zr0 * uR + pL - pR) / (zl0 + zr0);
    const double du_l = uL - u0 > 0.0 ? uL - u0 : 0.0, du_r = u0 - uR > 0.0 ? u0 - uR : 0.0;
    const double zl_s = zl0 + ZS[f - 1] * du_l, zr_s = zr0 + ZS[f] * du_r;
    const double zl = zl_s < ZMAX[f - 1] ? zl_s : ZMAX[f - 1], zr = zr_s < ZMAX[f] ? zr_s : ZMAX[f];
    const double zs = zl + zr;
    ustar[f] = (zl * uL + zr * uR + pL - pR) / zs;
    pstar[f] = (zr * pL + zl * pR + zl * zr * (uL - uR)) / zs;
  }
}

void solveFaces(Pencil& P, const SweepSetup& S, PencilLedger& ledger) {
  const double dt = S.dt, wall_u = S.wall_velocity[static_cast<std::size_t>(S.d)];
  const int g = kGhost, n = P.n;
  const int f0 = g - 1, f1 = g + n + 1;
  const double* dilatation = P.radial ? P.dil.data() : P.su.data();   // the predictor's (computeSlopes)
  // Every face as between two flow cells, in one branch-free loop (it vectorises); the faces beside
  // the body are overwritten below.
  {
    const double* un = P.u[static_cast<std::size_t>(S.d)].data();
    if (S.mixture_reuss)
      shockFaces(f0, f1, dt, S.width, un, P.su.data(), P.sp.data(), P.rho.data(), P.P.data(), P.Kp.data(), dilatation, P.Z.data(), P.zs.data(),
                 P.zmax.data(), P.ustar.data(), P.pstar.data());
    else
      acousticFaces(f0, f1, dt, S.width, un, P.su.data(), P.sp.data(), P.rho.data(), P.P.data(), P.Kp.data(), dilatation, P.Z.data(),
                    P.ustar.data(), P.pstar.data());
    if (P.radial && S.second_order) {
      // the hoop stress at the same half step as the face stresses it balances (lagrangeUpdate):
      // taken at the step's start it pushed an expanding ring outwards by a force that grew with the step
      for (int i = 1; i < P.N - 1; ++i) {
        const std::size_t si = static_cast<std::size_t>(i);
        P.hoop[si] -= 0.5 * dt * P.Kp[si] * P.dil[si];
      }
    }
    const double* ustar = P.ustar.data();
    const double* __restrict xf = S.xf;
    const double* __restrict area = P.area.data();
    double* __restrict dvol = P.dvol.data();
    if (P.spherical) {
      for (int f = f0; f <= f1; ++f) {
        const double rf = xf[f], r1 = rf + ustar[f] * dt;
        dvol[f] = (r1 * r1 * r1 - rf * rf * rf) / 3.0;
      }
    } else if (P.radial) {
      for (int f = f0; f <= f1; ++f) {
        const double rf = xf[f], disp = ustar[f] * dt;
        dvol[f] = P.ring_width * 0.5 * ((rf + disp) * std::abs(rf + disp) - rf * std::abs(rf));
      }
    } else {
      for (int f = f0; f <= f1; ++f) dvol[f] = area[f] * (ustar[f] * dt);
    }
  }
  if (!anySolid(P)) return;
  const auto& un = P.u[static_cast<std::size_t>(S.d)];
  for (int f = f0; f <= f1; ++f) {
    const std::size_t L = static_cast<std::size_t>(f - 1), R = static_cast<std::size_t>(f), sf = static_cast<std::size_t>(f);
    if (!(P.solid[L] | P.solid[R])) continue;
    // a wall moving with the body: the flow's half of the Riemann problem, no swept volume
    const auto [uL, pL, uR, pR] = hancockStates(f - 1, f, dt, S.width, un.data(), P.su.data(), P.sp.data(), P.rho.data(), P.P.data(), P.Kp.data(),
                                                dilatation);
    // the flow side takes the whole jump to the wall's velocity (mixture_reuss: its shock impedance)
    const double zl = S.mixture_reuss ? std::min(P.Z[L] + P.zs[L] * std::max(uL - wall_u, 0.0), P.zmax[L]) : P.Z[L];
    const double zr = S.mixture_reuss ? std::min(P.Z[R] + P.zs[R] * std::max(wall_u - uR, 0.0), P.zmax[R]) : P.Z[R];
    double ps = 0.0;
    if (!P.solid[L]) ps = std::max(pL + zl * (uL - wall_u), P.pmin[L]);
    else if (!P.solid[R]) ps = std::max(pR + zr * (wall_u - uR), P.pmin[R]);
    P.ustar[sf] = wall_u;
    P.pstar[sf] = ps;
    P.dvol[sf] = S.grid_disp ? P.area[sf] * S.grid_disp[sf] : 0.0;   // the wall and its mesh face move together
    // the load on the body at faces between an interior flow cell and an interior body cell
    // (a body cell in the ghost layer is the boundary's: its work is booked there)
    if ((P.solid[L] ^ P.solid[R]) && f >= g && f <= g + n) {
      const bool body_right = P.solid[R] != 0;
      if (!((body_right && f == g + n) || (!body_right && f == g))) {
        const std::size_t fluid = body_right ? L : R;
        const double sign = body_right ? 1.0 : -1.0;
        ledger.target_work += sign * ps * P.area[sf] * dt * wall_u;
        // by material against the ambient (reference) pressure: the air's share is then what the
        // blast adds to the air's push, not the atmosphere on the plate's top; over the closed
        // body the reference sums to zero, so the total is the load itself
        const double imp = sign * (ps - S.load_reference) * P.area[sf] * dt;
        // along axis 0 (the axis a domain is split along) a layer could reach past a slab's ghosts: the
        // cell's own fractions there, so that the split is the same on any number of slabs
        bookLoadByMaterial(P, S, static_cast<int>(fluid), body_right ? 1 : -1, static_cast<std::size_t>(S.d), sign * ps * P.area[sf] * dt, imp,
                           S.d == 0, ledger);
      }
    }
  }
}

// ------------------------------------------------------------------------------------------------

namespace {
// volumeWork with the polytrope's power (1 + x)^-G from `ratio(x)`, x = dv / v0 (for a compression
// no lower than -0.999), which the closure keeps for its step 2 (one power instead of two for a gas).
template <class Ratio>
double polytropeWork(double p, double K, double v0, double dv, Ratio&& ratio) {
  if (dv < 0.0 && v0 > 0.0 && p > 0.0) {
    // Compression to the same order: along the polytrope for a gas (G < 4), by the trapezoid for a
    // stiff material (its pressure rises by K x over the step). At p dV from the starting pressure
    // a soft gas beside sand, which takes nearly all of a cell's volume swings, fell short of its
    // adiabat on every compression, and the shortfall went to the sand (revision 4 measured the
    // confined products' energy at 10 ms: -4.7 kJ with the first-order credit, +129 kJ with this).
    const double x = std::max(dv / v0, -0.999), G = K / p;
    if (G > 1.0 + 1e-6 && G < 4.0) return p * v0 * (ratio(x) * (1.0 + x) - 1.0) / (G - 1.0);
    return -(p - 0.5 * K * x) * dv;
  }
  if (!(dv > 0.0) || !(p > 0.0) || !(v0 > 0.0)) return -p * dv;
  const double x = dv / v0, G = K / p;
  const double gm1 = std::max(G - 1.0, 1e-6);
  if (gm1 * x < 1e-6) return -p * dv * (1.0 - 0.5 * (gm1 + 1.0) * x);   // series for small steps
  const double power = gm1 == G - 1.0 ? ratio(x) * (1.0 + x) : std::pow(1.0 + x, -gm1);   // (1 + x)^(1 - G)
  return -p * v0 * (1.0 - power) / gm1;
}
}  // namespace

// Work done on a material whose volume v0 changes by dv, starting at pressure p with bulk modulus
// K: along the local polytrope p v^G = const, G = K/p, second order in dv/v0 both ways.
// Expanding: a small fraction of gas in an expanding cell takes most of the cell's volume change,
// often many times its own volume in one step; charged p dV at its starting pressure it would give
// away more than it holds and end below zero energy, where its pressure is cut to zero. Along the
// polytrope it gives at most p v0 / (G - 1), which for an ideal gas (and JWL products far out) is
// all it holds.
double volumeWork(double p, double K, double v0, double dv) {
  return polytropeWork(p, K, v0, dv, [&](double x) { return std::pow(1.0 + x, -K / p); });
}

void closeMixedCell(MixedCell& c, double V, double Vl, double die) {
  const int M = c.M;
  const double dV = Vl - V;
  int present = 0;
  double dv_frag = 0.0;
  for (int k = 0; k < M; ++k) {
    if (c.alpha[k] > kAlphaMin) {
      ++present;
    } else {
      dv_frag += c.alpha[k] * dV;
    }
  }
  if (present <= 1) {
    for (int k = 0; k < M; ++k) {
      c.v[k] = c.alpha[k] * Vl;
      if (c.alpha[k] > kAlphaMin) c.ie[k] += die;
    }
    return;
  }
  // 1. the volume change by compressibility, work at each material's own pressure. A material
  //    may not lose more than 95% of its volume in a step; what it cannot take goes to the others
  //    (by their compressibility), and each is charged for the change it actually makes.
  double work = 0.0, dv[kMaxMaterials];
  bool held[kMaxMaterials] = {};
  double remaining = dV - dv_frag;
  double compliance[kMaxMaterials];   // alpha / K: each one's share of the volume change
  for (int k = 0; k < M; ++k) {
    dv[k] = c.alpha[k] > kAlphaMin ? 0.0 : c.alpha[k] * dV;
    compliance[k] = c.alpha[k] / std::max(c.K[k], 1.0);
  }
  for (int pass = 0; pass < M; ++pass) {
    double w = 0.0;
    for (int k = 0; k < M; ++k)
      if (c.alpha[k] > kAlphaMin && !held[k]) w += compliance[k];
    if (!(w > 0.0)) break;
    const double per_w = remaining / w;
    bool clamped = false;
    for (int k = 0; k < M; ++k) {
      if (c.alpha[k] <= kAlphaMin || held[k]) continue;
      dv[k] = compliance[k] * per_w;
      if (dv[k] < -0.95 * c.alpha[k] * V) {
        dv[k] = -0.95 * c.alpha[k] * V;
        held[k] = true;
        clamped = true;
      }
    }
    if (!clamped) break;
    remaining = dV - dv_frag;
    for (int k = 0; k < M; ++k)
      if (held[k]) remaining -= dv[k];
  }
  // (1 + x)^-G where step 1 took it (a gas, or a stiff material expanding), else -1: step 2's
  // pressure of a gas. Step 1 keeps x >= -0.95, so the x it was taken at is step 2's.
  double ratio[kMaxMaterials];
  for (int k = 0; k < M; ++k) {
    c.v[k] = c.alpha[k] * V + dv[k];
    ratio[k] = -1.0;
    if (c.alpha[k] > kAlphaMin) {
      const double v0 = c.alpha[k] * V;
      const double wk = polytropeWork(c.p[k], c.K[k], v0, dv[k], [&](double x) { return ratio[k] = std::pow(1.0 + x, -c.K[k] / c.p[k]); });
      c.ie[k] += wk;
      work += wk;
    }
  }
  // 2. pressure relaxation. Each material's pressure after step 1's volume change (along its
  //    polytrope, or linearly for a stiff one), their linearised common pressure p_eq, and each
  //    material moved towards it (at most half its volume lost, or its volume gained, per step)
  //    working at p_eq: the exchanged volumes sum to zero, so nothing changes hands beyond
  //    p_eq dv and no heat is routed. The relaxation's dissipation stays where it arises: an
  //    expanding material keeps what its isentrope would have given beyond p_eq dv, a compressed
  //    one is worked at p_eq, above its own pressure (the interface-pressure closure of Saurel,
  //    Petitpas and Berry, and of Kamm and Shashkov). Charged at its own pressure instead, the
  //    expanding material gave that excess away as heat, mostly by mass into sand: confined
  //    products lost energy with every refinement (119 / 52 / 29 / 18 kJ at 10 / 6 / 5 / 4 mm).
  double p1[kMaxMaterials] = {}, K1[kMaxMaterials] = {}, vk_per_K[kMaxMaterials] = {};
  double sw = 0.0, swp = 0.0;
  for (int k = 0; k < M; ++k) {
    if (c.alpha[k] <= kAlphaMin) continue;
    const double v0 = c.alpha[k] * V, p = c.p[k], x = dv[k] / v0;   // step 1 keeps 5% of v0
    if (p > 0.0 && c.K[k] / p < 4.0) {   // a gas, as volumeWork: along p v^G = const, G = K / p
      const double G = c.K[k] / p;
      p1[k] = p * (ratio[k] >= 0.0 ? ratio[k] : std::pow(1.0 + x, -G));
      K1[k] = std::max(G * p1[k], 1.0);
    } else {   // stiff, or at no pressure: linearly, never extrapolated below zero from a
               // material that was not in tension (a zero-pressure one would then be charged
               // a negative price and end below zero energy)
      K1[k] = std::max(c.K[k], 1.0);
      p1[k] = std::max(p - K1[k] * x, std::min(p, 0.0));
    }
    vk_per_K[k] = c.v[k] / K1[k];
    sw += vk_per_K[k];
    swp += vk_per_K[k] * p1[k];
  }
  const double p_eq = swp / sw;
  double theta = 1.0, step[kMaxMaterials] = {};
  for (int k = 0; k < M; ++k) {
    if (c.alpha[k] <= kAlphaMin) continue;
    const double dk = step[k] = vk_per_K[k] * (p1[k] - p_eq);
    if (dk < 0.0) theta = std::min(theta, 0.5 * c.v[k] / -dk);
    if (dk > 0.0) theta = std::min(theta, c.v[k] / dk);
  }
  for (int k = 0; k < M; ++k) {
    if (c.alpha[k] <= kAlphaMin) continue;
    const double dk = theta * step[k];
    c.v[k] += dk;
    c.ie[k] -= p_eq * dk;
    work -= p_eq * dk;   // sums to round-off: booked, so that step 3 closes the cell exactly
  }
  // keep the material volumes summing to the cell's
  double vs = 0.0;
  for (int k = 0; k < M; ++k) vs += c.v[k];
  for (int k = 0; k < M; ++k) c.v[k] *= Vl / vs;
  // 3. the rest of the energy change (dissipation, shear work): a gain by compression (by the
  //    magnitude of p dV where nothing was compressed), never more than twice the cell's mean per
  //    unit mass to one material, the remainder by mass; a loss by what each material holds.
  const double rest = die - work;
  double wsq = 0.0, wpdv = 0.0, msum = 0.0, share[kMaxMaterials] = {};
  for (int k = 0; k < M; ++k) {
    if (c.alpha[k] <= kAlphaMin) continue;
    wsq += std::max(c.alpha[k] * V - c.v[k], 0.0);
    wpdv += std::abs(c.p[k] * (c.v[k] - c.alpha[k] * V));
    msum += c.m[k];
  }
  if (rest >= 0.0) {
    double given = 0.0;
    for (int k = 0; k < M; ++k) {
      if (c.alpha[k] <= kAlphaMin) continue;
      const double wk = wsq > 0.0 ? std::max(c.alpha[k] * V - c.v[k], 0.0) / wsq
                                  : (wpdv > 0.0 ? std::abs(c.p[k] * (c.v[k] - c.alpha[k] * V)) / wpdv : c.m[k] / msum);
      share[k] = msum > 0.0 ? std::min(rest * wk, 2.0 * rest * c.m[k] / msum) : rest * wk;
      given += share[k];
    }
    for (int k = 0; k < M; ++k)
      if (c.alpha[k] > kAlphaMin) c.ie[k] += share[k] + (msum > 0.0 ? (rest - given) * c.m[k] / msum : 0.0);
  } else {
    double held_ie = 0.0, taken = 0.0;
    for (int k = 0; k < M; ++k)
      if (c.alpha[k] > kAlphaMin) held_ie += std::max(c.ie[k], 0.0);
    for (int k = 0; k < M; ++k) {
      if (c.alpha[k] <= kAlphaMin) continue;
      share[k] = held_ie > 0.0 ? std::max(-std::max(c.ie[k], 0.0), rest * std::max(c.ie[k], 0.0) / held_ie) : 0.0;
      taken += share[k];
    }
    for (int k = 0; k < M; ++k)
      if (c.alpha[k] > kAlphaMin) c.ie[k] += share[k] + (msum > 0.0 ? (rest - taken) * c.m[k] / msum : 0.0);
  }
}

namespace {
// Cells i0 .. i1 - 1 of the Lagrange phase along axis D: momentum and total energy in flux form,
// the kinetic energy after it and the internal energy change `die`, gravity's work per cell.
// Walls: the pencil has body cells (no shear traction on the body's faces). Friction: the Coulomb
// friction on the body's faces too (the cells beside the body, one by one). Without either, a
// plain loop over restrict-qualified arrays that vectorises. The same arithmetic in the same order
// in every variant.
template <int D, bool Walls, bool Friction>
[[gnu::noinline]] void lagrangeCells(std::ptrdiff_t i0, std::ptrdiff_t i1, double dt, double grav, double hoop_on, const double* __restrict vol,
                          const double* __restrict dvol, const double* __restrict area, const double* __restrict pstar,
                          const double* __restrict ustar, const double* __restrict hoop, const double* __restrict mass,
                          const double* __restrict ie_cell, const double* __restrict u0, const double* __restrict u1,
                          const double* __restrict u2, const double* __restrict sh0, const double* __restrict sh1,
                          const unsigned char* __restrict solid, double* __restrict vlag, double* __restrict mom0, double* __restrict mom1,
                          double* __restrict mom2, double* __restrict ke, double* __restrict die, double* __restrict w_grav,
                          const Pencil* P = nullptr, const SweepSetup* S = nullptr, PencilLedger* ledger = nullptr, bool interior = false) {
  constexpr int T1 = (D + 1) % 3, T2 = (D + 2) % 3;
  // (chosen at compile time: a pointer read back from an array would lose its restrict)
  const auto velocity = [&](auto axis) -> const double* {
    constexpr int q = decltype(axis)::value;
    if constexpr (q == 0) return u0;
    else if constexpr (q == 1) return u1;
    else return u2;
  };
  const double* __restrict const un = velocity(std::integral_constant<int, D>{});
  for (std::ptrdiff_t i = i0; i < i1; ++i) {
    const std::ptrdiff_t fr = i + 1;
    const double V = vol[i];
    vlag[i] = V + dvol[fr] - dvol[i];
    const double m = mass[i], ie = ie_cell[i];
    const double Al = area[i], Ar = area[fr];
    double ke0 = 0.0;
    ke0 += 0.5 * m * u0[i] * u0[i];
    ke0 += 0.5 * m * u1[i] * u1[i];
    ke0 += 0.5 * m * u2[i] * u2[i];
    double E = ie + ke0 - dt * (Ar * pstar[fr] * ustar[fr] - Al * pstar[i] * ustar[i]);
    // normal momentum: faces, hoop stress (axisymmetric or spherical r: the areas' growth, dA, times
    // the mean hoop stress), gravity
    const double mn = m * un[i] - dt * (Ar * pstar[fr] - Al * pstar[i]) + dt * (Ar - Al) * hoop[i] * hoop_on;
    const double mn_g = mn + dt * m * grav;
    const double wg = dt * grav * 0.5 * (mn + mn_g);
    E += wg;
    w_grav[i] = wg;
    double mom_new[3];
    mom_new[D] = mn_g;
    // transverse momentum from the shear tractions (free slip on the body: no shear traction)
    const auto transverse = [&](auto comp_constant, const double* __restrict s) {
      constexpr int comp = decltype(comp_constant)::value;
      const double* __restrict const ut = velocity(comp_constant);
      double tr = 0.5 * (s[i] + s[i + 1]), tl = 0.5 * (s[i - 1] + s[i]);
      if constexpr (Walls) {
        if (solid[i] | solid[i + 1]) tr = 0.0;
        if (solid[i - 1] | solid[i]) tl = 0.0;
      }
      const double ur = 0.5 * (ut[i] + ut[i + 1]), ul = 0.5 * (ut[i - 1] + ut[i]);
      mom_new[comp] = m * ut[i] + dt * (Ar * tr - Al * tl);
      E += dt * (Ar * tr * ur - Al * tl * ul);
    };
    transverse(std::integral_constant<int, T1>{}, sh0);
    transverse(std::integral_constant<int, T2>{}, sh1);
    if constexpr (Friction) {
      // Coulomb friction on the body's face: mu times the compressive normal stress on the part of
      // the contact held by materials with strength (frictionGrip: a gas slides freely), against
      // the sliding in the face's plane (both transverse components at once: a diagonal slide takes
      // mu p, not sqrt(2) mu p), never reversing it within a step. The body gains the momentum the
      // flow loses and the work at its own velocity; the rest of the kinetic energy removed stays in
      // the cell's total energy, i.e. becomes heat.
      const double held = frictionGrip(*P, static_cast<int>(i)), grip = std::min(held, 1.0);
      const double pn = std::max(solid[i + 1] ? pstar[fr] : 0.0, 0.0) * Ar + std::max(solid[i - 1] ? pstar[i] : 0.0, 0.0) * Al;
      const double s1 = mom_new[T1] - m * S->wall_velocity[T1], s2 = mom_new[T2] - m * S->wall_velocity[T2];
      const double slide = std::hypot(s1, s2);
      if (grip > 0.0 && slide > 0.0) {
        const double f = std::min(S->friction * grip * pn * dt, slide) / slide;
        const double taken[2] = {f * s1, f * s2};
        mom_new[T1] -= taken[0];
        mom_new[T2] -= taken[1];
        const double w_body = taken[0] * S->wall_velocity[T1] + taken[1] * S->wall_velocity[T2];
        E -= w_body;
        if (interior) {
          ledger->target_work += w_body;
          for (int c = 0; c < 2; ++c)
            if (taken[c] != 0.0) bookFriction(*P, *S, static_cast<int>(i), static_cast<std::size_t>(c == 0 ? T1 : T2), taken[c], held, *ledger);
        }
      }
    }
    const double inv_m = 1.0 / m;
    double ke1 = 0.0;
    ke1 += 0.5 * mom_new[0] * mom_new[0] * inv_m;
    ke1 += 0.5 * mom_new[1] * mom_new[1] * inv_m;
    ke1 += 0.5 * mom_new[2] * mom_new[2] * inv_m;
    mom0[i] = mom_new[0];
    mom1[i] = mom_new[1];
    mom2[i] = mom_new[2];
    ke[i] = ke1;
    die[i] = E - ke1 - ie;
  }
}

template <int D>
void lagrangeAlong(Pencil& P, const SweepSetup& S, PencilLedger& ledger) {
  const int g = kGhost, n = P.n;
  const double hoop_on = P.radial ? 1.0 : 0.0;
  const auto run = [&](auto walls, auto friction, std::ptrdiff_t i0, std::ptrdiff_t i1, bool interior) {
    lagrangeCells<D, decltype(walls)::value, decltype(friction)::value>(
        i0, i1, S.dt, S.gravity, hoop_on, P.vol.data(), P.dvol.data(), P.area.data(), P.pstar.data(), P.ustar.data(), P.hoop.data(),
        P.mass.data(), P.ie_cell.data(), P.u[0].data(), P.u[1].data(), P.u[2].data(), P.shear[0].data(), P.shear[1].data(), P.solid.data(),
        P.vlag.data(), P.mom[0].data(), P.mom[1].data(), P.mom[2].data(), P.ke.data(), P.die.data(), P.w_grav.data(), &P, &S, &ledger,
        interior);
  };
  if (!anySolid(P)) {
    run(std::false_type{}, std::false_type{}, g - 1, g + n + 1, false);
    return;
  }
  run(std::true_type{}, std::false_type{}, g - 1, g + n + 1, false);
  if (S.friction > 0.0) {
    // the cells beside the body again, with the friction (the same arithmetic, in the same order)
    for (int i = g - 1; i <= g + n; ++i) {
      const std::size_t si = static_cast<std::size_t>(i);
      if (!P.solid[si] && (P.solid[si - 1] | P.solid[si + 1])) run(std::true_type{}, std::true_type{}, i, i + 1, i >= g && i < g + n);
    }
  }
}
// One material's mass and internal energy in cells i0 .. i1 - 1, added to the cells' sums (in the
// materials' order), and whether it is present (above kAlphaMin).
[[gnu::noinline]] void materialMassAndEnergy(std::ptrdiff_t i0, std::ptrdiff_t i1, const double* __restrict a, const double* __restrict r,
                                             const double* __restrict e, const double* __restrict vol, double* __restrict mk,
                                             double* __restrict iek, double* __restrict mass, double* __restrict ie,
                                             double* __restrict present) {
  for (std::ptrdiff_t i = i0; i < i1; ++i) {
    present[i] += a[i] > kAlphaMin ? 1.0 : 0.0;
    mk[i] = a[i] * r[i] * vol[i];
    iek[i] = mk[i] * e[i];
    mass[i] += mk[i];
    ie[i] += iek[i];
  }
}

// closeMixedCell's own answer for the cells of one material (at most one above kAlphaMin), without
// the copies: each material's volume alpha Vl, the heat to the one present. Mixed cells keep their
// values here (the closure sets them).
[[gnu::noinline]] void singleMaterialClosure(std::ptrdiff_t i0, std::ptrdiff_t i1, const double* __restrict a, const double* __restrict vlag,
                                             const double* __restrict die, const double* __restrict present, double* __restrict vk,
                                             double* __restrict iek) {
  for (std::ptrdiff_t i = i0; i < i1; ++i) {
    const bool single = present[i] <= 1.0;
    vk[i] = single ? a[i] * vlag[i] : vk[i];
    iek[i] = (single & (a[i] > kAlphaMin)) ? iek[i] + die[i] : iek[i];
  }
}
}  // namespace

void lagrangeUpdate(Pencil& P, const SweepSetup& S, PencilLedger& ledger) {
  const int g = kGhost, n = P.n, M = P.M;
  const double dt = S.dt;
  const std::ptrdiff_t i0 = g - 1, i1 = g + n + 1;
  // each material's mass and internal energy, the cell's sums in the materials' order
  for (std::ptrdiff_t i = i0; i < i1; ++i) {
    const std::size_t si = static_cast<std::size_t>(i);
    P.mass[si] = 0.0;
    P.ie_cell[si] = 0.0;
    P.present[si] = 0.0;
  }
  for (int k = 0; k < M; ++k) {
    const std::size_t base = P.at(k, 0);
    materialMassAndEnergy(i0, i1, P.a.data() + base, P.r.data() + base, P.e.data() + base, P.vol.data(), P.mk.data() + base,
                          P.iek.data() + base, P.mass.data(), P.ie_cell.data(), P.present.data());
  }
  switch (S.d) {
    case 0: lagrangeAlong<0>(P, S, ledger); break;
    case 1: lagrangeAlong<1>(P, S, ledger); break;
    default: lagrangeAlong<2>(P, S, ledger); break;
  }
  double gravity_work = ledger.gravity_work;   // in the cells' order
  for (std::ptrdiff_t i = g; i < g + n; ++i) {
    const std::size_t si = static_cast<std::size_t>(i);
    if (!P.solid[si]) gravity_work += P.w_grav[si];   // the body's cells are not the flow's
  }
  // The closure: a cell of one material takes closeMixedCell's own answer (singleMaterialClosure),
  // a mixed cell the closure itself.
  for (int k = 0; k < M; ++k) {
    const std::size_t base = P.at(k, 0);
    singleMaterialClosure(i0, i1, P.a.data() + base, P.vlag.data(), P.die.data(), P.present.data(), P.vk.data() + base, P.iek.data() + base);
  }
  for (std::ptrdiff_t i = i0; i < i1; ++i) {
    const std::size_t si = static_cast<std::size_t>(i);
    if (P.present[si] <= 1.0) continue;
    MixedCell c;
    c.M = M;
    for (int k = 0; k < M; ++k) {
      const std::size_t ki = P.at(k, static_cast<int>(i));
      c.alpha[k] = P.a[ki];
      c.p[k] = P.pk[ki];
      c.K[k] = P.kk[ki];
      c.m[k] = P.mk[ki];
      c.ie[k] = P.iek[ki];
    }
    closeMixedCell(c, P.vol[si], P.vlag[si], P.die[si]);
    for (int k = 0; k < M; ++k) {
      const std::size_t ki = P.at(k, static_cast<int>(i));
      P.vk[ki] = c.v[k];
      P.iek[ki] = c.ie[k];
    }
  }
  ledger.gravity_work = gravity_work;
  // Work at the pencil's end faces (normal stress and shear tractions): energy in or out of the block.
  const auto shearWork = [&](int f) {
    const std::size_t sf = static_cast<std::size_t>(f);
    if (P.solid[sf - 1] | P.solid[sf]) return 0.0;
    double w = 0.0;
    for (int tt = 0; tt < 2; ++tt) {
      const auto& sh = P.shear[static_cast<std::size_t>(tt)];
      const auto& ut = P.u[static_cast<std::size_t>(tt == 0 ? S.t1 : S.t2)];
      w += 0.5 * (sh[sf - 1] + sh[sf]) * 0.5 * (ut[sf - 1] + ut[sf]);
    }
    return w;
  };
  const std::size_t lo = static_cast<std::size_t>(g), hi = static_cast<std::size_t>(g + n);
  if (!P.solid[lo] && S.lo_is_boundary) ledger.boundary_in += dt * P.area[lo] * (P.pstar[lo] * P.ustar[lo] - shearWork(g));
  if (!P.solid[hi - 1] && S.hi_is_boundary) ledger.boundary_in -= dt * P.area[hi] * (P.pstar[hi] * P.ustar[hi] - shearWork(g + n));
}

// ------------------------------------------------------------------------------------------------

// THINC's profile at each cell's two faces, cells i0 .. i1 of every material: where the cell has
// a profile (thincCentre), alpha(x) = (1 + gamma tanh(beta (x - xc))) / 2 at x = 0 and 1, which with
// t = exp(2 beta xc) are 1 / (1 + t) and E / (E + t) (gamma = +1; E = exp(2 beta)), or t / (1 + t)
// and t / (E + t) (gamma = -1); elsewhere the cell's fraction at both.
void thincFaceValues(Pencil& P, int i0, int i1, const ThincProfile& th) {
  const double E = th.exp_beta * th.exp_beta;
  for (int k = 0; k < P.M; ++k)
    for (int i = i0; i <= i1; ++i) {
      const std::size_t c = P.at(k, i);
      const double a = P.a[c];
      double gamma = 0.0, t = 0.0;
      if (!thincCentre(a, P.a[c - 1], P.a[c + 1], th, gamma, t)) {
        P.tlo[c] = P.thi[c] = a;
        continue;
      }
      P.tlo[c] = gamma > 0.0 ? 1.0 / (1.0 + t) : t / (1.0 + t);
      P.thi[c] = gamma > 0.0 ? E / (E + t) : t / (E + t);
    }
}

// Whether the donor takes THINC's step (SolverOptions::thinc_bvd). Where the fractions within two
// cells either side reach both a near-pure low (<= kNearPure) and a near-pure high (>= 1 - kNearPure),
// the donor is on an interface: the step, as without the option, so that an interface spread over
// two or three cells is sharpened again (a BVD choice against the donor mean alone would leave a
// 0 | 1/3 | 2/3 | 1 ramp to the mean, whose diffusion then spreads it further). Elsewhere BVD
// (boundary variation diminishing; Sun, Inaba & Xiao 2016, Deng et al. 2018): the step where the
// jumps it leaves at the donor's two faces, against its neighbours' profiles, are smaller than those
// of the donor mean against theirs. In a dust of sand in gas (0.049 | 0.05 | 0.051) the step would
// put the cell's whole fraction against one face, a jump the mean does not make: seeding stripes.
bool bvdTakesTheProfile(const Pencil& P, std::size_t c) {
  constexpr double kNearPure = 0.1;
  double lo = P.a[c], hi = P.a[c];
  for (const std::size_t q : {c - 2, c - 1, c + 1, c + 2}) {
    lo = std::min(lo, P.a[q]);
    hi = std::max(hi, P.a[q]);
  }
  if (lo <= kNearPure && hi >= 1.0 - kNearPure) return true;
  const double tbv_thinc = std::abs(P.thi[c - 1] - P.tlo[c]) + std::abs(P.thi[c] - P.tlo[c + 1]);
  const double tbv_mean = std::abs(P.a[c - 1] - P.a[c]) + std::abs(P.a[c] - P.a[c + 1]);
  return tbv_thinc < tbv_mean;
}

void remapFluxes(Pencil& P, const SweepSetup& S, PencilLedger& ledger) {
  const int g = kGhost, n = P.n, M = P.M;
  const bool second = S.second_order;
  const ThincProfile thinc(S.thinc_beta);
  // every flux through faces g .. g+n starts at zero (one fill per array, not eleven stores a face)
  for (int k = 0; k < M; ++k) {
    const auto lo = static_cast<std::ptrdiff_t>(P.atFace(k, g)), hi = static_cast<std::ptrdiff_t>(P.atFace(k, g + n)) + 1;
    for (auto* v : {&P.fv, &P.fm, &P.fe, &P.fh, &P.fkek}) std::fill(v->begin() + lo, v->begin() + hi, 0.0);
    if (!P.strengthless[k])
      for (auto& fs : P.fs) std::fill(fs.begin() + lo, fs.begin() + hi, 0.0);
  }
  for (auto& fm : P.fmom) std::fill(fm.begin() + g, fm.begin() + g + n + 1, 0.0);
  const bool bvd = M > 1 && S.thinc_bvd;
  if (bvd) thincFaceValues(P, g - 2, g + n + 1, thinc);
  for (int f = g; f <= g + n; ++f) {
    const std::size_t sf = static_cast<std::size_t>(f);
    const double dvf = (P.solid[sf - 1] | P.solid[sf]) ? 0.0 : (S.grid_disp ? P.dvol[sf] - P.area[sf] * S.grid_disp[sf] : P.dvol[sf]);
    if (dvf == 0.0) continue;
    const bool out_high = dvf > 0.0;
    const int D = out_high ? f - 1 : f;
    const std::size_t sD = static_cast<std::size_t>(D);
    const double sign = out_high ? 1.0 : -1.0;
    const double vD = P.vlag[sD];
    const double bfrac = std::min(std::abs(dvf) / vD, 1.0);
    const double offset = sign * 0.5 * S.width[sD] * (1.0 - bfrac);
    // material volumes: THINC where an interface faces the sweep, the donor mean elsewhere,
    // normalised to the swept volume and never more than a donor holds
    double raw_sum = 0.0, raw[kMaxMaterials];
    ThincFace face(bfrac, out_high, thinc);
    for (int k = 0; k < M; ++k) {
      const std::size_t kD = P.at(k, D);
      if (M > 1 && P.vk[kD] == 0.0 && vD > 0.0) {
        // none of it in the donor (most materials at most faces of a pencil of several): the +0
        // that the profile and the mean give, without the division and the profile's call; the sum
        // starts at +0 and adds no negative term, so adding +0 to it changed no bit
        raw[k] = 0.0;
        continue;
      }
      const double al = P.vk[kD] / vD;
      const double wl = P.wl[kD];
      if (bvd && !bvdTakesTheProfile(P, kD)) raw[k] = al * bfrac;
      else raw[k] = M == 1 ? bfrac : wl * thincOutflow(al, P.a[kD - 1], P.a[kD + 1], face) + (1.0 - wl) * al * bfrac;
      raw_sum += raw[k];
    }
    const double target = std::abs(dvf);
    // no profile anywhere (never met in practice): by the donor's volumes, which do not depend on
    // the materials the pencil carries
    double held = 0.0;
    if (!(raw_sum > 0.0))
      for (int k = 0; k < M; ++k) held += P.vk[P.at(k, D)];
    double dvk[kMaxMaterials], excess = 0.0, room = 0.0;
    const double per_raw = raw_sum > 0.0 ? target / raw_sum : 0.0;
    for (int k = 0; k < M; ++k) {
      const std::size_t kD = P.at(k, D);
      // (a material with no profile here takes nothing: +0; one that has the whole of it, a pure
      // donor's, the swept volume exactly)
      dvk[k] = raw_sum > 0.0 ? (raw[k] == 0.0 ? 0.0 : (raw[k] == raw_sum ? target : raw[k] * per_raw))
                             : (held > 0.0 ? P.vk[kD] / held * target : target / M);
      if (dvk[k] > P.vk[kD]) {
        excess += dvk[k] - P.vk[kD];
        dvk[k] = P.vk[kD];
      } else {
        room += P.vk[kD] - dvk[k];
      }
    }
    if (excess > 0.0 && room > 0.0)
      for (int k = 0; k < M; ++k) {
        const std::size_t kD = P.at(k, D);
        if (dvk[k] < P.vk[kD]) dvk[k] += excess * (P.vk[kD] - dvk[k]) / room;
      }
    double dm = 0.0, mflux_k[kMaxMaterials] = {};
    for (int k = 0; k < M; ++k) {
      const std::size_t kD = P.at(k, D), kf = P.atFace(k, f);
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
          const double il = S.inv_dx[sD], ir = S.inv_dx[sD + 1];
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
      if (!P.strengthless[k])
        for (std::size_t q = 0; q < 6; ++q) P.fs[q][kf] = sign * mflux * P.s[q][kD];
      mflux_k[k] = mflux;
      dm += mflux;
    }
    const double keep_m = dm > 0.0 ? std::clamp((P.mass[sD] - dm) / dm, 0.0, 1.0) : 1.0;
    double uf2 = 0.0;
    const Reciprocal per_mass(P.mass[sD]);
    for (std::size_t q = 0; q < 3; ++q) {
      const auto& uq = P.u[q];
      double uf = per_mass.of(P.mom[q][sD]);
      if (second) uf += keep_m * offset * vanLeer((uq[sD] - uq[sD - 1]) * S.inv_dx[sD], (uq[sD + 1] - uq[sD]) * S.inv_dx[sD + 1]);
      P.fmom[q][sf] = sign * dm * uf;
      uf2 += uf * uf;
    }
    double eflow = 0.0;   // total energy through this face
    for (int k = 0; k < M; ++k) {
      const std::size_t kf = P.atFace(k, f);
      P.fkek[kf] = sign * 0.5 * mflux_k[k] * uf2;
      eflow += P.fe[kf] + P.fkek[kf];
    }
    if ((f == g && S.lo_is_boundary) || (f == g + n && S.hi_is_boundary)) {
      const double in = f == g ? 1.0 : -1.0;   // into the block
      ledger.boundary_in += in * eflow;
      for (int k = 0; k < M; ++k) ledger.boundary_mass[P.mat[k]] += in * P.fm[P.atFace(k, f)];
    }
  }
}

void moveCellVolumes(Pencil& P, const SweepSetup& S) {
  for (int i = kGhost; i < kGhost + P.n; ++i) {
    const std::size_t si = static_cast<std::size_t>(i);
    P.vol[si] += P.area[si + 1] * S.grid_disp[si + 1] - P.area[si] * S.grid_disp[si];
  }
}

}  // namespace ejecta::hydro
