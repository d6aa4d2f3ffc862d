#include "mesh/grid.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace ejecta::mesh {

Axis::Axis(std::vector<double> faces) : faces_(std::move(faces)) {
  if (faces_.size() < 2) throw InputError("mesh", "an axis needs at least one cell");
  for (std::size_t f = 1; f < faces_.size(); ++f)
    if (!(faces_[f] > faces_[f - 1]) || !std::isfinite(faces_[f]))
      throw InputError("mesh", fmt::format("face coordinates must increase strictly (face {} at {:g} m)", f, faces_[f]));
}

Axis Axis::uniform(double lo, double hi, int cells) {
  if (!(hi > lo)) throw InputError("mesh", fmt::format("axis end {:g} m must exceed its start {:g} m", hi, lo));
  if (cells < 1) throw InputError("mesh", "an axis needs at least one cell");
  std::vector<double> f(static_cast<std::size_t>(cells) + 1);
  for (int c = 0; c <= cells; ++c) f[static_cast<std::size_t>(c)] = lo + (hi - lo) * c / cells;
  f.back() = hi;
  return Axis(std::move(f));
}

Axis Axis::graded(double lo, double hi, double core_lo, double core_hi, double dx, double ratio, std::optional<double> anchor) {
  if (!(dx > 0.0)) throw InputError("mesh.cell_size", "must be > 0 m");
  if (!(ratio >= 1.0 && ratio <= 1.5)) throw InputError("mesh.grading", fmt::format("{:g} is out of range; valid [1, 1.5]", ratio));
  if (!(lo <= core_lo && core_lo < core_hi && core_hi <= hi))
    throw InputError("mesh", "the uniform core must lie inside the domain");
  std::vector<double> f;
  if (anchor && *anchor > core_lo && *anchor < core_hi) {
    const double a = *anchor;
    auto count = [dx](double span, double room) {   // whole cells over `span`, none past `room`
      int n = static_cast<int>(std::lround(span / dx));
      while (n > 0 && n * dx > room * (1.0 + 1e-12)) --n;
      return n;
    };
    const int below = count(a - core_lo, a - lo), above = count(core_hi - a, hi - a);
    if (below + above < 1) throw InputError("mesh.cell_size", fmt::format("{:g} m is larger than the uniform core", dx));
    for (int c = -below; c <= above; ++c) f.push_back(a + c * dx);
    core_lo = a - below * dx;
    core_hi = a + above * dx;
  } else {
    const int n_core = std::max(1, static_cast<int>(std::lround((core_hi - core_lo) / dx)));
    for (int c = 0; c <= n_core; ++c) f.push_back(core_lo + (core_hi - core_lo) * c / n_core);
  }
  // Grow outward; a last cell under half its predecessor is merged into it.
  auto grow = [&](double from, double to, double sign) {
    std::vector<double> out;
    double w = dx, x = from;
    while (sign * (to - x) > 1e-12 * std::abs(to - from) + 0.0) {
      w *= ratio;
      double next = x + sign * w;
      if (sign * (to - next) < 0.5 * w) next = to;
      out.push_back(next);
      x = next;
    }
    return out;
  };
  const auto up = grow(core_hi, hi, 1.0);
  const auto down = grow(core_lo, lo, -1.0);
  std::vector<double> all(down.rbegin(), down.rend());
  all.insert(all.end(), f.begin(), f.end());
  all.insert(all.end(), up.begin(), up.end());
  return Axis(std::move(all));
}

double Axis::minWidth() const {
  double w = faces_[1] - faces_[0];
  for (std::size_t f = 1; f + 1 < faces_.size(); ++f) w = std::min(w, faces_[f + 1] - faces_[f]);
  return w;
}

Grid::Grid(int dims, Geometry geometry, std::array<Axis, 3> axes) : dims_(dims), geometry_(geometry), axes_(std::move(axes)) {
  if (dims < 1 || dims > 3) throw InputError("mesh.dims", "must be 1, 2 or 3");
  if (geometry == Geometry::Axisymmetric) {
    if (dims != 2) throw InputError("mesh.geometry", "axisymmetric meshes are 2D (r, z)");
    if (axes_[0].lo() < 0.0) throw InputError("mesh.r", "the radial axis must start at r >= 0 m");
  }
  if (geometry == Geometry::Spherical) {
    if (dims != 1) throw InputError("mesh.geometry", "spherical meshes are 1D (r)");
    if (axes_[0].lo() < 0.0) throw InputError("mesh.r", "the radial axis must start at r >= 0 m");
  }
  for (int d = 0; d < 3; ++d) {
    const auto sd = static_cast<std::size_t>(d);
    if (d >= dims) axes_[sd] = Axis::uniform(0.0, 1.0, 1);
    n_[sd] = axes_[sd].cells();
    g_[sd] = ghost(d);
    axisGeometry(d);
  }
  stride_[2] = 1;
  stride_[1] = n_[2] + 2 * g_[2];
  stride_[0] = stride_[1] * (n_[1] + 2 * g_[1]);
  total_ = static_cast<std::size_t>(stride_[0] * (n_[0] + 2 * g_[0]));
  global0_ = n_[0];
}

Grid Grid::slab(int begin, int end) const {
  if (isSlab()) throw InputError("mesh", "a slab is cut from the whole grid");
  if (begin < 0 || end > n_[0] || end - begin < kGhost)
    throw InputError("mesh", fmt::format("a slab [{}, {}) of {} cells needs at least {} cells", begin, end, n_[0], kGhost));
  const auto& f = axes_[0].faces();
  Grid s(dims_, geometry_, {Axis(std::vector<double>(f.begin() + begin, f.begin() + end + 1)), axes_[1], axes_[2]});
  // ghost geometry along axis 0 from the whole grid: entries [f + g] for faces f in [begin - g, end + g]
  const int g = g_[0];
  s.fx_[0].assign(fx_[0].begin() + begin, fx_[0].begin() + end + 2 * g + 1);
  for (std::size_t c = 0; c < s.xc_[0].size(); ++c) {
    s.xc_[0][c] = 0.5 * (s.fx_[0][c] + s.fx_[0][c + 1]);
    s.dx_[0][c] = s.fx_[0][c + 1] - s.fx_[0][c];
  }
  s.offset0_ = begin;
  s.global0_ = n_[0];
  s.whole_faces0_ = f;
  return s;
}

void Grid::axisGeometry(int d) {
  const auto sd = static_cast<std::size_t>(d);
  const int n = n_[sd], g = g_[sd];
  const auto& f = axes_[sd].faces();
  // Ghost faces mirror the widths of the cells next to the boundary.
  fx_[sd].resize(static_cast<std::size_t>(n + 2 * g + 1));
  for (int q = 0; q <= n; ++q) fx_[sd][static_cast<std::size_t>(q + g)] = f[static_cast<std::size_t>(q)];
  for (int q = 1; q <= g; ++q) {
    const int in_lo = std::min(q, n), in_hi = std::max(n - q, 0);
    fx_[sd][static_cast<std::size_t>(g - q)] = f[0] - (f[static_cast<std::size_t>(in_lo)] - f[0]);
    fx_[sd][static_cast<std::size_t>(n + g + q)] = f[static_cast<std::size_t>(n)] + (f[static_cast<std::size_t>(n)] - f[static_cast<std::size_t>(in_hi)]);
  }
  xc_[sd].resize(static_cast<std::size_t>(n + 2 * g));
  dx_[sd].resize(static_cast<std::size_t>(n + 2 * g));
  for (std::size_t c = 0; c < xc_[sd].size(); ++c) {
    xc_[sd][c] = 0.5 * (fx_[sd][c] + fx_[sd][c + 1]);
    dx_[sd][c] = fx_[sd][c + 1] - fx_[sd][c];
  }
}

void Grid::moveFaces(int d, Axis moved) {
  if (d < 0 || d >= dims_ || moved.cells() != n_[static_cast<std::size_t>(d)])
    throw InputError("mesh", "a moved axis must keep its number of cells");
  if (d == 0 && curvilinear()) throw InputError("mesh", "the radial axis of an axisymmetric or spherical mesh does not move");
  if (d == 0 && isSlab()) throw InputError("mesh", "the axis a slab was cut along does not move");
  axes_[static_cast<std::size_t>(d)] = std::move(moved);
  axisGeometry(d);
}

Index3 Grid::unflatten(std::size_t flat) const {
  const auto f = static_cast<std::ptrdiff_t>(flat);
  Index3 ix;
  ix.i = static_cast<int>(f / stride_[0]) - g_[0];
  ix.j = static_cast<int>((f % stride_[0]) / stride_[1]) - g_[1];
  ix.k = static_cast<int>(f % stride_[1]) - g_[2];
  return ix;
}

bool Grid::isInterior(std::size_t flat) const {
  const Index3 ix = unflatten(flat);
  return ix.i >= 0 && ix.i < n_[0] && ix.j >= 0 && ix.j < n_[1] && ix.k >= 0 && ix.k < n_[2];
}

double Grid::cellVolume(int i, int j, int k) const {
  if (spherical()) {   // r^3 is odd: a ghost cell mirrored through r = 0 has its mirror's volume
    const double rl = face(0, i), rr = face(0, i + 1);
    return (rr * rr * rr - rl * rl * rl) / 3.0;
  }
  if (axisymmetric()) {
    const double rl = face(0, i), rr = face(0, i + 1);
    return 0.5 * std::abs(rr * std::abs(rr) - rl * std::abs(rl)) * width(1, j);
  }
  return width(0, i) * width(1, j) * width(2, k);
}

double Grid::faceArea(int d, int i, int j, int k) const {
  if (spherical()) return d == 0 ? face(0, i) * face(0, i) : 0.0;
  if (axisymmetric()) {
    if (d == 0) return std::abs(face(0, i)) * width(1, j);
    if (d == 1) return 0.5 * std::abs(face(0, i + 1) * std::abs(face(0, i + 1)) - face(0, i) * std::abs(face(0, i)));
    return 0.0;
  }
  double a = 1.0;
  for (int t = 0; t < 3; ++t)
    if (t != d) a *= width(t, t == 0 ? i : (t == 1 ? j : k));
  return a;
}

double Grid::minWidth() const {
  double w = axes_[0].minWidth();
  for (int d = 1; d < dims_; ++d) w = std::min(w, axes_[static_cast<std::size_t>(d)].minWidth());
  return w;
}

}  // namespace ejecta::mesh
