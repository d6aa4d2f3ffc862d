#include "hydro/rezone.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "hydro/pencil.hpp"

namespace ejecta::hydro {

namespace {
// Target cell index along axis d holding the source cell's centre; -1 outside the target.
std::vector<int> targetIndex(const mesh::Grid& src, const mesh::Grid& dst, int d) {
  std::vector<int> out(static_cast<std::size_t>(src.cells(d)), -1);
  const auto& f = dst.axis(d).faces();
  for (int i = 0; i < src.cells(d); ++i) {
    const double x = src.centre(d, i);
    if (d >= dst.dims()) {
      out[static_cast<std::size_t>(i)] = 0;
      continue;
    }
    if (x <= f.front() || x >= f.back()) continue;
    out[static_cast<std::size_t>(i)] = static_cast<int>(std::upper_bound(f.begin(), f.end(), x) - f.begin()) - 1;
  }
  return out;
}
// Per target cell, per material ([cell * M + k]): the sums of what the source cells put there (and,
// in 3D, of the target's own part outside the source), then written into the target's cells.
struct Sums {
  std::size_t M = 0;
  std::vector<double> vol, vk, mk, iek, hk, kek;
  std::vector<std::array<double, 6>> sk;   // mass x deviatoric stress, with strength
  std::vector<Vec3> mom;
  Sums(std::size_t cells, std::size_t materials, bool strength)
      : M(materials), vol(cells, 0.0), vk(cells * materials, 0.0), mk(cells * materials, 0.0), iek(cells * materials, 0.0),
        hk(cells * materials, 0.0), kek(cells * materials, 0.0), mom(cells, Vec3{}) {
    if (strength) sk.assign(cells * materials, std::array<double, 6>{});
  }
  // a volume V of cell `from` of solver s, as it is, into target cell `into`
  void add(const Solver& s, std::size_t from, std::size_t into, double V) {
    vol[into] += V;
    double u2 = 0.0;
    for (int d = 0; d < 3; ++d) u2 += s.velocity(d)[from] * s.velocity(d)[from];
    for (std::size_t k = 0; k < M; ++k) {
      const auto& F = s.field(static_cast<int>(k));
      if (F.alpha[from] <= 0.0) continue;
      const std::size_t q = into * M + k;
      const double m = F.alpha[from] * F.rho[from] * V;
      vk[q] += F.alpha[from] * V;
      mk[q] += m;
      iek[q] += m * F.e[from];
      hk[q] += m * F.h0[from];
      kek[q] += 0.5 * m * u2;
      if (!F.s[0].empty() && !sk.empty())
        for (std::size_t j = 0; j < 6; ++j) sk[q][j] += m * F.s[j][from];
      for (std::size_t d = 0; d < 3; ++d) mom[into][d] += m * s.velocity(static_cast<int>(d))[from];
    }
  }
};

bool anyStrength(const Solver& s) {
  for (int k = 0; k < s.materialCount(); ++k)
    if (!s.field(k).s[0].empty()) return true;
  return false;
}

void checkSameMaterials(const Solver& source, const Solver& target) {
  if (source.materialCount() != target.materialCount()) throw InputError("rezone", "the two solvers differ in materials");
  for (int k = 0; k < source.materialCount(); ++k)
    if (source.materials()[static_cast<std::size_t>(k)].name != target.materials()[static_cast<std::size_t>(k)].name)
      throw InputError("rezone", "the two solvers' materials differ");
}

// Writes every target cell that received sums: each material's volume fraction, density (its mass
// exactly), energy, history and stress; one velocity (the momentum exactly); the kinetic energy
// that velocity cannot hold as heat, to each material as it lost it.
void writeSums(Sums& S, Solver& target, RezoneReport& rep) {
  const auto& tg = target.grid();
  const std::size_t uM = S.M;
  const int M = static_cast<int>(uM);
  for (int I = 0; I < tg.cells(0); ++I)
    for (int J = 0; J < tg.cells(1); ++J)
      for (int L = 0; L < tg.cells(2); ++L) {
        const std::size_t tc = tg.index(I, J, L);
        if (S.vol[tc] <= 0.0) continue;
        const double V = tg.cellVolume(I, J, L);
        if (std::abs(S.vol[tc] - V) > 1e-9 * V || target.isBody(tc))
          throw InputError("rezone", fmt::format("target cell ({}, {}, {}) at ({:.4g}, {:.4g}, {:.4g}) m is not covered exactly by source cells "
                                                 "(volume {:.6g} of {:.6g}{}; the meshes must nest)",
                                                 I, J, L, tg.centre(0, I), tg.centre(1, J), tg.centre(2, L), S.vol[tc], V, target.isBody(tc) ? ", a body cell" : ""));
        ++rep.target_cells;
        double m = 0.0, vsum = 0.0;
        for (std::size_t k = 0; k < uM; ++k) {
          m += S.mk[tc * uM + k];
          vsum += S.vk[tc * uM + k];
        }
        Vec3 u{};
        double U2 = 0.0;
        for (std::size_t d = 0; d < 3; ++d) {
          u[d] = m > 0.0 ? S.mom[tc][d] / m : 0.0;
          U2 += u[d] * u[d];
        }
        double m_new[kMaxMaterials], loss[kMaxMaterials], add[kMaxMaterials], held[kMaxMaterials], heat = 0.0;
        for (std::size_t k = 0; k < uM; ++k) {
          const std::size_t q = tc * uM + k;
          m_new[k] = S.mk[q];
          held[k] = S.iek[q];
          loss[k] = S.kek[q] - 0.5 * S.mk[q] * U2;
          heat += loss[k];
        }
        shareHeat(M, m_new, loss, heat, held, add);
        rep.heat_by_cell.push_back(heat);
        for (int k = 0; k < M; ++k) {
          auto& F = target.fieldForSetup(k);
          const std::size_t q = tc * uM + static_cast<std::size_t>(k);
          // a trace with no volume to hold it (a source fraction that underflowed: 1e-300 kg)
          if (S.mk[q] <= 0.0 || S.vk[q] <= 0.0) {
            F.clearCell(tc);
            continue;
          }
          F.alpha[tc] = S.vk[q] / vsum;
          F.rho[tc] = S.mk[q] / (F.alpha[tc] * V);   // the mass exactly
          F.e[tc] = (S.iek[q] + add[k]) / S.mk[q];
          F.h0[tc] = S.hk[q] / S.mk[q];
          if (!F.s[0].empty())
            for (std::size_t c = 0; c < 6; ++c) F.s[c][tc] = S.sk.empty() ? 0.0 : S.sk[q][c] / S.mk[q];
        }
        target.setVelocity(tc, u);
      }
}
}  // namespace

RezoneReport mapNested(const Solver& source, Solver& target) {
  const auto& sg = source.grid();
  const auto& tg = target.grid();
  checkSameMaterials(source, target);
  if (sg.dims() != tg.dims() || sg.geometry() != tg.geometry()) throw InputError("rezone", "the two solvers differ in geometry");
  const std::array<std::vector<int>, 3> map{targetIndex(sg, tg, 0), targetIndex(sg, tg, 1), targetIndex(sg, tg, 2)};
  Sums S(tg.totalCells(), static_cast<std::size_t>(source.materialCount()), anyStrength(source));
  RezoneReport rep;
  for (int i = 0; i < sg.cells(0); ++i)
    for (int j = 0; j < sg.cells(1); ++j)
      for (int l = 0; l < sg.cells(2); ++l) {
        const int I = map[0][static_cast<std::size_t>(i)], J = map[1][static_cast<std::size_t>(j)], L = map[2][static_cast<std::size_t>(l)];
        if (I < 0 || J < 0 || L < 0) continue;
        const std::size_t sc = sg.index(i, j, l), tc = tg.index(I, J, L);
        if (source.isBody(sc)) continue;
        ++rep.source_cells;
        S.add(source, sc, tc, sg.cellVolume(i, j, l));
      }
  writeSums(S, target, rep);
  return rep;
}

namespace {
// The nodes and weights of a 16-point Gauss-Legendre rule on [-1, 1] (Newton on P_16, once).
struct GaussRule {
  std::vector<double> x, w;
};
const GaussRule& gaussLegendre() {
  static const GaussRule rule = [] {
    constexpr int n = 16;
    GaussRule r;
    for (int i = 0; i < n; ++i) {
      double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = z;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1.0);
        const double dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-16) break;
      }
      r.x.push_back(z);
      r.w.push_back(2.0 / ((1.0 - z * z) * dp * dp));
    }
    return r;
  }();
  return rule;
}
}  // namespace

RingOverlap ringOverlap(double x0, double x1, double y0, double y1, double r0, double r1) {
  RingOverlap o;
  const double a = std::max(r0, std::hypot(x0, y0)), b = std::min(r1, std::hypot(x1, y1));
  if (!(b > a)) return o;
  // Where a circle of radius r crosses the rectangle it is one arc, theta in [lo, hi] (cos falls
  // and sin rises over the quadrant); the arc's ends change form where r passes a side or a corner.
  auto arc = [&](double r, double& lo, double& hi) {
    lo = std::max(r > x1 ? std::acos(x1 / r) : 0.0, r > y0 ? std::asin(y0 / r) : 0.5 * M_PI);
    hi = std::min(r > x0 ? std::acos(x0 / r) : -1.0, r > y1 ? std::asin(y1 / r) : 0.5 * M_PI);
    return hi > lo;
  };
  std::vector<double> cuts{a, b};
  for (const double c : {x0, x1, y0, y1, std::hypot(x0, y1), std::hypot(x1, y0)})
    if (c > a && c < b) cuts.push_back(c);
  std::sort(cuts.begin(), cuts.end());
  // Gauss-Legendre on each piece after r = mid + half sin(pi t / 2), which smooths the square-root
  // behaviour of the arc's ends at the pieces' ends
  const auto& gl = gaussLegendre();
  for (std::size_t p = 0; p + 1 < cuts.size(); ++p) {
    const double mid = 0.5 * (cuts[p] + cuts[p + 1]), half = 0.5 * (cuts[p + 1] - cuts[p]);
    if (!(half > 0.0)) continue;
    for (std::size_t g = 0; g < gl.x.size(); ++g) {
      const double t = 0.5 * M_PI * gl.x[g];
      const double r = mid + half * std::sin(t), w = gl.w[g] * half * 0.5 * M_PI * std::cos(t) * r;
      double lo = 0.0, hi = 0.0;
      if (!arc(r, lo, hi)) continue;
      o.area += w * (hi - lo);
      o.cos += w * (std::sin(hi) - std::sin(lo));
      o.sin += w * (std::cos(lo) - std::cos(hi));
      o.cos2 += w * 0.5 * (std::sin(2.0 * hi) - std::sin(2.0 * lo));
      o.sin2 += w * 0.5 * (std::cos(2.0 * lo) - std::cos(2.0 * hi));
    }
  }
  return o;
}

RezoneReport mapAxisymmetricToQuarter(const Solver& source, Solver& target) {
  const auto& sg = source.grid();
  const auto& tg = target.grid();
  checkSameMaterials(source, target);
  if (sg.dims() != 2 || sg.geometry() != mesh::Geometry::Axisymmetric || tg.dims() != 3 || tg.geometry() != mesh::Geometry::Cartesian)
    throw InputError("rezone", "an axisymmetric (r, z) state maps into a 3D Cartesian (x, y, z) quarter");
  // A slab of the quarter (an MPI rank's) takes the pieces of its own columns, each ring scaled over
  // the whole's columns: every cell the same sums, in the same order, as in the whole.
  const auto &rf = sg.axis(0).faces(), &xf = tg.wholeFaces0(), &yf = tg.axis(1).faces();
  const int x_off = tg.offset0(), x_end = tg.offset0() + tg.cells(0);
  if (rf.front() != 0.0 || xf.front() != 0.0 || yf.front() != 0.0 || std::min(xf.back(), yf.back()) < rf.back())
    throw InputError("rezone", "the quarter (x, y >= 0) must start on the axis and hold the source's whole radius");
  // along z the meshes nest (writeSums checks each cell's volume is covered)
  const auto& zf = tg.axis(2).faces();
  std::vector<int> zmap3(static_cast<std::size_t>(sg.cells(1)), -1);
  for (int j = 0; j < sg.cells(1); ++j) {
    const double z = sg.centre(1, j);
    if (!(z > zf.front() && z < zf.back()))   // what lies beyond the quarter's height would be lost
      throw InputError("rezone", fmt::format("the axisymmetric source's layer at z = {:.4g} m lies outside the quarter's height ({:.4g} to {:.4g} m)", z,
                                             zf.front(), zf.back()));
    zmap3[static_cast<std::size_t>(j)] = static_cast<int>(std::upper_bound(zf.begin(), zf.end(), z) - zf.begin()) - 1;
  }
  const int nr = sg.cells(0), nx = static_cast<int>(xf.size()) - 1, ny = tg.cells(1);
  // each ring's overlap with each column (x, y) of the quarter, scaled so that the ring's area and
  // its first moments sum exactly over the columns (the mass and the momentum then map exactly)
  struct Piece { int ring, column; RingOverlap o; };
  std::vector<Piece> pieces;
  std::vector<RingOverlap> ring_sum(static_cast<std::size_t>(nr));
  for (int I = 0; I < nx; ++I)
    for (int J = 0; J < ny; ++J) {
      const double x0 = xf[static_cast<std::size_t>(I)], x1 = xf[static_cast<std::size_t>(I) + 1], y0 = yf[static_cast<std::size_t>(J)],
                   y1 = yf[static_cast<std::size_t>(J) + 1];
      if (std::hypot(x0, y0) >= rf.back()) continue;
      const auto first = std::upper_bound(rf.begin(), rf.end(), std::hypot(x0, y0)) - rf.begin() - 1;
      for (auto i = std::max<std::ptrdiff_t>(first, 0); i < nr; ++i) {
        const double r0 = rf[static_cast<std::size_t>(i)], r1 = rf[static_cast<std::size_t>(i) + 1];
        if (r0 >= std::hypot(x1, y1)) break;
        const RingOverlap o = ringOverlap(x0, x1, y0, y1, r0, r1);
        if (!(o.area > 0.0)) continue;
        pieces.push_back({static_cast<int>(i), I * ny + J, o});
        auto& s = ring_sum[static_cast<std::size_t>(i)];
        s.area += o.area;
        s.cos += o.cos;
        s.sin += o.sin;
      }
    }
  for (int i = 0; i < nr; ++i) {
    const double r0 = rf[static_cast<std::size_t>(i)], r1 = rf[static_cast<std::size_t>(i) + 1];
    const double exact = 0.25 * M_PI * (r1 * r1 - r0 * r0);
    if (std::abs(ring_sum[static_cast<std::size_t>(i)].area - exact) > 1e-6 * exact)
      throw InputError("rezone", fmt::format("the ring r = {:.4g} to {:.4g} m does not lie in the quarter's columns", r0, r1));
  }
  for (auto& p : pieces) {
    const double r0 = rf[static_cast<std::size_t>(p.ring)], r1 = rf[static_cast<std::size_t>(p.ring) + 1];
    const auto& s = ring_sum[static_cast<std::size_t>(p.ring)];
    const double area = 0.25 * M_PI * (r1 * r1 - r0 * r0), moment = 0.5 * (r1 * r1 - r0 * r0);
    p.o.area *= area / s.area;
    p.o.cos *= moment / s.cos;
    p.o.sin *= moment / s.sin;
  }
  const std::size_t uM = static_cast<std::size_t>(source.materialCount());
  Sums S(tg.totalCells(), uM, anyStrength(source));   // per target cell
  RezoneReport rep;
  std::vector<double> covered(static_cast<std::size_t>(nx * ny), 0.0);
  std::vector<char> layer_hit(static_cast<std::size_t>(tg.cells(2)), 0);
  for (const auto& p : pieces) covered[static_cast<std::size_t>(p.column)] += p.o.area;
  for (int j = 0; j < sg.cells(1); ++j) {
    const int L = zmap3[static_cast<std::size_t>(j)];
    if (L < 0) continue;
    layer_hit[static_cast<std::size_t>(L)] = 1;
    const double dz = sg.axis(1).faces()[static_cast<std::size_t>(j) + 1] - sg.axis(1).faces()[static_cast<std::size_t>(j)];
    for (const auto& p : pieces) {
      const int I = p.column / ny - x_off;
      if (I < 0 || I >= tg.cells(0)) continue;   // another slab's column
      const std::size_t sc = sg.index(p.ring, j, 0), tc = tg.index(I, p.column % ny, L);
      if (source.isBody(sc)) throw InputError("rezone", "the axisymmetric source holds a body: map before the flow reaches the target");
      if (target.isBody(tc))
        throw InputError("rezone", fmt::format("the axisymmetric state reaches the 3D target's cell at ({:.4g}, {:.4g}, {:.4g}) m: map before the flow reaches it",
                                               tg.centre(0, I), tg.centre(1, p.column % ny), tg.centre(2, L)));
      ++rep.source_cells;
      const double a = p.o.area * dz;
      S.vol[tc] += a;
      const double ur = source.velocity(0)[sc], uz = source.velocity(1)[sc], ut = source.velocity(2)[sc];
      const double u2 = ur * ur + uz * uz + ut * ut;
      for (std::size_t k = 0; k < uM; ++k) {
        const auto& F = source.field(static_cast<int>(k));
        if (F.alpha[sc] <= 0.0) continue;
        const std::size_t q = tc * uM + k;
        const double rho = F.alpha[sc] * F.rho[sc], m = rho * a;
        S.vk[q] += F.alpha[sc] * a;
        S.mk[q] += m;
        S.iek[q] += m * F.e[sc];
        S.hk[q] += m * F.h0[sc];
        S.kek[q] += 0.5 * m * u2;
        // momentum and stress turned from (r, z, theta) into (x, y, z) over the piece
        const double mc = p.o.cos * dz, ms = p.o.sin * dz, mc2 = p.o.cos2 * dz, ms2 = p.o.sin2 * dz;   // the piece's moments
        S.mom[tc][0] += rho * (ur * mc - ut * ms);
        S.mom[tc][1] += rho * (ur * ms + ut * mc);
        S.mom[tc][2] += m * uz;
        if (!F.s[0].empty() && !S.sk.empty()) {
          const double srr = F.s[0][sc], szz = F.s[1][sc], stt = F.s[2][sc], srz = F.s[3][sc], szt = F.s[4][sc], srt = F.s[5][sc];
          auto& st = S.sk[q];
          st[0] += rho * (0.5 * srr * (a + mc2) + 0.5 * stt * (a - mc2) - srt * ms2);
          st[1] += rho * (0.5 * srr * (a - mc2) + 0.5 * stt * (a + mc2) + srt * ms2);
          st[2] += m * szz;
          st[3] += rho * (0.5 * (srr - stt) * ms2 + srt * mc2);
          st[4] += rho * (srz * ms + szt * mc);   // y-z
          st[5] += rho * (srz * mc - szt * ms);   // x-z
        }
      }
    }
  }
  // a column the source covers in part keeps its own contents in the rest
  for (int I = x_off; I < x_end; ++I)
    for (int J = 0; J < ny; ++J) {
      const double A = (xf[static_cast<std::size_t>(I) + 1] - xf[static_cast<std::size_t>(I)]) * (yf[static_cast<std::size_t>(J) + 1] - yf[static_cast<std::size_t>(J)]);
      const double f = std::min(covered[static_cast<std::size_t>(I * ny + J)] / A, 1.0);
      if (!(f > 0.0) || f > 1.0 - 1e-12) continue;
      for (int L = 0; L < tg.cells(2); ++L) {
        const std::size_t tc = tg.index(I - x_off, J, L);
        if (!layer_hit[static_cast<std::size_t>(L)] || target.isBody(tc)) continue;
        S.add(target, tc, tc, (1.0 - f) * tg.cellVolume(I - x_off, J, L));
      }
    }
  writeSums(S, target, rep);
  return rep;
}

}  // namespace ejecta::hydro
