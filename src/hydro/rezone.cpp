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
}  // namespace

RezoneReport mapNested(const Solver& source, Solver& target) {
  const auto& sg = source.grid();
  const auto& tg = target.grid();
  const int M = source.materialCount();
  if (M != target.materialCount() || sg.dims() != tg.dims() || sg.geometry() != tg.geometry())
    throw InputError("rezone", "the two solvers differ in materials or geometry");
  for (int k = 0; k < M; ++k)
    if (source.materials()[static_cast<std::size_t>(k)].name != target.materials()[static_cast<std::size_t>(k)].name)
      throw InputError("rezone", "the two solvers' materials differ");
  const std::array<std::vector<int>, 3> map{targetIndex(sg, tg, 0), targetIndex(sg, tg, 1), targetIndex(sg, tg, 2)};
  const std::size_t total = tg.totalCells();
  const auto uM = static_cast<std::size_t>(M);
  // sums per target cell: [cell * M + k]
  std::vector<double> vol(total, 0.0), vk(total * uM, 0.0), mk(total * uM, 0.0), iek(total * uM, 0.0), hk(total * uM, 0.0), kek(total * uM, 0.0);
  std::vector<std::array<double, 6>> sk;
  bool strength = false;
  for (int k = 0; k < M; ++k) strength = strength || !source.field(k).s[0].empty();
  if (strength) sk.assign(total * uM, std::array<double, 6>{});
  std::vector<Vec3> mom(total, Vec3{});
  RezoneReport rep;
  for (int i = 0; i < sg.cells(0); ++i)
    for (int j = 0; j < sg.cells(1); ++j)
      for (int l = 0; l < sg.cells(2); ++l) {
        const int I = map[0][static_cast<std::size_t>(i)], J = map[1][static_cast<std::size_t>(j)], L = map[2][static_cast<std::size_t>(l)];
        if (I < 0 || J < 0 || L < 0) continue;
        const std::size_t sc = sg.index(i, j, l), tc = tg.index(I, J, L);
        if (source.isBody(sc)) continue;
        ++rep.source_cells;
        const double V = sg.cellVolume(i, j, l);
        vol[tc] += V;
        double u2 = 0.0;
        for (int d = 0; d < 3; ++d) u2 += source.velocity(d)[sc] * source.velocity(d)[sc];
        for (int k = 0; k < M; ++k) {
          const auto& F = source.field(k);
          if (F.alpha[sc] <= 0.0) continue;
          const std::size_t q = tc * uM + static_cast<std::size_t>(k);
          const double m = F.alpha[sc] * F.rho[sc] * V;
          vk[q] += F.alpha[sc] * V;
          mk[q] += m;
          iek[q] += m * F.e[sc];
          hk[q] += m * F.h0[sc];
          kek[q] += 0.5 * m * u2;
          if (!F.s[0].empty())
            for (std::size_t c = 0; c < 6; ++c) sk[q][c] += m * F.s[c][sc];
          for (int d = 0; d < 3; ++d) mom[tc][static_cast<std::size_t>(d)] += m * source.velocity(d)[sc];
        }
      }
  for (int I = 0; I < tg.cells(0); ++I)
    for (int J = 0; J < tg.cells(1); ++J)
      for (int L = 0; L < tg.cells(2); ++L) {
        const std::size_t tc = tg.index(I, J, L);
        if (vol[tc] <= 0.0) continue;
        const double V = tg.cellVolume(I, J, L);
        if (std::abs(vol[tc] - V) > 1e-9 * V || target.isBody(tc))
          throw InputError("rezone", fmt::format("target cell ({}, {}, {}) at ({:.4g}, {:.4g}, {:.4g}) m is not covered exactly by source cells "
                                                 "(volume {:.6g} of {:.6g}{}; the meshes must nest)",
                                                 I, J, L, tg.centre(0, I), tg.centre(1, J), tg.centre(2, L), vol[tc], V, target.isBody(tc) ? ", a body cell" : ""));
        ++rep.target_cells;
        double m = 0.0, vsum = 0.0;
        for (int k = 0; k < M; ++k) {
          m += mk[tc * uM + static_cast<std::size_t>(k)];
          vsum += vk[tc * uM + static_cast<std::size_t>(k)];
        }
        Vec3 u{};
        double U2 = 0.0;
        for (std::size_t d = 0; d < 3; ++d) {
          u[d] = m > 0.0 ? mom[tc][d] / m : 0.0;
          U2 += u[d] * u[d];
        }
        double m_new[kMaxMaterials], loss[kMaxMaterials], add[kMaxMaterials], held[kMaxMaterials], heat = 0.0;
        for (int k = 0; k < M; ++k) {
          const std::size_t q = tc * uM + static_cast<std::size_t>(k);
          m_new[k] = mk[q];
          held[k] = iek[q];
          loss[k] = kek[q] - 0.5 * mk[q] * U2;
          heat += loss[k];
        }
        shareHeat(M, m_new, loss, heat, held, add);
        rep.heat_J += heat;
        for (int k = 0; k < M; ++k) {
          auto& F = target.fieldForSetup(k);
          const std::size_t q = tc * uM + static_cast<std::size_t>(k);
          if (mk[q] <= 0.0) {
            F.clearCell(tc);
            continue;
          }
          F.alpha[tc] = vk[q] / vsum;
          F.rho[tc] = mk[q] / (F.alpha[tc] * V);   // the mass exactly
          F.e[tc] = (iek[q] + add[k]) / mk[q];
          F.h0[tc] = hk[q] / mk[q];
          if (!F.s[0].empty())
            for (std::size_t c = 0; c < 6; ++c) F.s[c][tc] = sk[q][c] / mk[q];
        }
        target.setVelocity(tc, u);
      }
  return rep;
}

}  // namespace ejecta::hydro
