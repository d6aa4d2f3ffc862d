#include "verify/problems.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "core/error.hpp"
#include "hydro/rezone.hpp"
#include "hydro/solver.hpp"
#include "verify/exact.hpp"

namespace ejecta::verify {

using hydro::Solver;
using hydro::SolverOptions;
using hydro::Vec3;
using materials::Material;
using mesh::Axis;
using mesh::BoundaryKind;
using mesh::Geometry;
using mesh::Grid;

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void setAll(SolverOptions& o, BoundaryKind k) {
  for (auto& a : o.boundary) a = {k, k};
}

// Largest drift of the books: each material's mass (held, plus what it folded into others, less
// what came in across the boundaries: hydro::EnergyLedger) against its start, over the largest of
// the masses involved; and the energy books' imbalance, what the cells hold against what they
// started with plus what crossed the boundaries, over the larger of the two totals.
double drift(const hydro::Totals& a, const hydro::Totals& b) {
  double worst = 0.0;
  for (std::size_t k = 0; k < a.mass.size(); ++k) {
    const double books = b.massBooks(k) - a.massBooks(k);
    const double scale = std::max({a.mass[k], b.mass[k], std::abs(b.boundary_mass[k] - a.boundary_mass[k])});
    if (scale > 0.0) worst = std::max(worst, std::abs(books) / scale);
  }
  const double scale = std::max(std::abs(a.total()), std::abs(b.total()));
  return std::max(worst, std::abs(b.total() - b.accounted(a.total())) / scale);
}
constexpr double kBooksLimit = 1e-10;   // every row's conservation column, checked

// Observed orders between consecutive rows of one problem from `first` on; NaN for the coarsest.
void fillOrders(std::vector<Row>& rows, std::size_t first, const std::string& problem) {
  const Row* prev = nullptr;
  for (std::size_t r = first; r < rows.size(); ++r) {
    if (rows[r].problem != problem) continue;
    const Row& cur = rows[r];
    rows[r].order = (prev && prev->error > 0.0 && cur.error > 0.0)
                        ? std::log(prev->error / cur.error) / std::log(static_cast<double>(cur.resolution) / prev->resolution)
                        : kNaN;
    prev = &rows[r];
  }
}

double gasEnergy(double p, double rho, double gamma) { return p / ((gamma - 1.0) * rho); }

// Index of the cell containing coordinate x along axis d (interior cells only).
int cellAt(const Grid& g, int d, double x) {
  const auto& f = g.axis(d).faces();
  const auto it = std::upper_bound(f.begin(), f.end(), x);
  return std::clamp(static_cast<int>(it - f.begin()) - 1, 0, g.cells(d) - 1);
}

// ------------------------------------------------------------------------------------------------
// Sod's shock tube along axis `axis`: L1 density error at t = 0.2 against the exact solution.
void sod(int axis, const std::vector<int>& levels, Report& rep) {
  const char* names[] = {"sod-x", "sod-y", "sod-z"};
  const std::size_t first = rep.rows.size();
  const ExactRiemann exact({1.0, 0.0, 1.0}, {0.125, 0.0, 0.1}, 1.4);
  for (const int n : levels) {
    const auto t0 = std::chrono::steady_clock::now();
    const int dims = axis == 2 ? 3 : 2;
    std::array<Axis, 3> ax{Axis::uniform(0.0, 2.0 / n, 2), Axis::uniform(0.0, 2.0 / n, 2), Axis::uniform(0.0, 2.0 / n, 2)};
    ax[static_cast<std::size_t>(axis)] = Axis::uniform(0.0, 1.0, n);
    SolverOptions o;
    setAll(o, BoundaryKind::Periodic);
    o.boundary[static_cast<std::size_t>(axis)] = {BoundaryKind::Transmit, BoundaryKind::Transmit};
    Solver s(Grid(dims, Geometry::Cartesian, ax), {materials::idealGas("gas", 1.4)}, o);
    s.paint(0, [](const Vec3&) { return true; }, 0.125, gasEnergy(0.1, 0.125, 1.4));
    s.paint(0, [axis](const Vec3& x) { return x[static_cast<std::size_t>(axis)] < 0.5; }, 1.0, gasEnergy(1.0, 1.0, 1.4), {}, 1);
    const auto before = s.totals();
    s.advanceTo(0.2);
    const auto after = s.totals();
    Profile prof{names[axis], n, "x", "density", {}, {}, {}};
    double l1 = 0.0, l1_shock = 0.0;
    for (int c = 0; c < n; ++c) {
      int ix[3] = {0, 0, 0};
      ix[axis] = c;
      const double x = s.grid().centre(axis, c);
      const double rho = s.density(s.grid().index(ix[0], ix[1], ix[2]));
      const double ex = exact.sample((x - 0.5) / 0.2).rho;
      l1 += std::abs(rho - ex) / n;
      if (x > 0.75 && x < 0.95) l1_shock += std::abs(rho - ex) / n;   // the shock is at x = 0.850
      prof.x.push_back(x);
      prof.numeric.push_back(rho);
      prof.exact.push_back(ex);
    }
    rep.profiles.push_back(std::move(prof));
    rep.rows.push_back({names[axis], dims == 3 ? "3D" : "2D plane", "L1(density)", n, s.grid().interiorCells(), l1, 0.0,
                        drift(before, after), seconds(t0), "", true, s.stats().steps});
    rep.rows.push_back({std::string(names[axis]) + "-shock", dims == 3 ? "3D" : "2D plane", "L1(density), 0.75 < x < 0.95", n,
                        s.grid().interiorCells(), l1_shock, 0.0, kNaN, 0.0, "", true});
  }
  fillOrders(rep.rows, first, names[axis]);
  fillOrders(rep.rows, first, std::string(names[axis]) + "-shock");
  auto& whole = rep.rows[rep.rows.size() - 2];
  whole.check = "order >= 0.8 (includes the contact)";
  whole.passed = whole.order >= 0.8;
  auto& shock = rep.rows.back();
  shock.check = "order >= 0.9 at the shock";
  shock.passed = shock.order >= 0.9;
}

// A smooth density wave carried by a uniform flow through a periodic box and back to its start:
// second order expected. dims = 1 (along x) or 2 (along the diagonal, which tests the splitting).
void smoothAdvection(int dims, const std::vector<int>& levels, Report& rep) {
  const std::string name = dims == 1 ? "advection-1d" : "advection-2d";
  const std::size_t first = rep.rows.size();
  const double pi2 = 2.0 * M_PI;
  for (const int n : levels) {
    const auto t0 = std::chrono::steady_clock::now();
    std::array<Axis, 3> ax{Axis::uniform(0.0, 1.0, n), dims == 2 ? Axis::uniform(0.0, 1.0, n) : Axis::uniform(0.0, 1.0, 1),
                           Axis::uniform(0.0, 1.0, 1)};
    SolverOptions o;
    setAll(o, BoundaryKind::Periodic);
    Solver s(Grid(dims, Geometry::Cartesian, ax), {materials::idealGas("gas", 1.4)}, o);
    s.paint(0, [](const Vec3&) { return true; }, 1.0, 1.0);
    auto& F = s.fieldForSetup(0);
    const Grid& g = s.grid();
    // cell averages of rho = 1 + 0.2 sin(2 pi (x + y))
    auto average = [&](int i, int j) {
      const double xl = g.face(0, i), xr = g.face(0, i + 1);
      if (dims == 1) return 1.0 + 0.2 * (std::cos(pi2 * xl) - std::cos(pi2 * xr)) / (pi2 * (xr - xl));
      const double yl = g.face(1, j), yr = g.face(1, j + 1);
      const double sx = (std::sin(pi2 * xr) - std::sin(pi2 * xl)), cx = (std::cos(pi2 * xr) - std::cos(pi2 * xl));
      const double sy = (std::sin(pi2 * yr) - std::sin(pi2 * yl)), cy = (std::cos(pi2 * yr) - std::cos(pi2 * yl));
      // integral of sin(a + b) = -(cos a) integral... via sin(a+b) = sin a cos b + cos a sin b
      const double integral = (-cx * sy + sx * -cy) / (pi2 * pi2);
      return 1.0 + 0.2 * integral / ((xr - xl) * (yr - yl));
    };
    std::vector<double> initial;
    for (int i = 0; i < g.cells(0); ++i)
      for (int j = 0; j < g.cells(1); ++j) {
        const std::size_t c = g.index(i, j, 0);
        F.rho[c] = average(i, j);
        F.e[c] = gasEnergy(1.0, F.rho[c], 1.4);
        s.setVelocity(c, {1.0, dims == 2 ? 1.0 : 0.0, 0.0});
        initial.push_back(F.rho[c]);
      }
    const auto before = s.totals();
    s.advanceTo(1.0);
    const auto after = s.totals();
    double l1 = 0.0;
    std::size_t q = 0;
    Profile prof{name, n, dims == 1 ? "x" : "x (along y = 0.5)", "density", {}, {}, {}};
    for (int i = 0; i < g.cells(0); ++i)
      for (int j = 0; j < g.cells(1); ++j, ++q) {
        const std::size_t c = g.index(i, j, 0);
        l1 += std::abs(s.density(c) - initial[q]) / static_cast<double>(g.interiorCells());
        if (j == g.cells(1) / 2) {
          prof.x.push_back(g.centre(0, i));
          prof.numeric.push_back(s.density(c));
          prof.exact.push_back(initial[q]);
        }
      }
    rep.profiles.push_back(std::move(prof));
    rep.rows.push_back({name, dims == 1 ? "1D" : "2D plane", "L1(density)", n, g.interiorCells(), l1, 0.0, drift(before, after),
                        seconds(t0), "", true, s.stats().steps});
  }
  fillOrders(rep.rows, first, name);
  auto& last = rep.rows.back();
  last.check = "order >= 1.8 (smooth flow)";
  last.passed = last.order >= 1.8;
}

// Radius of a shock: the density binned by radius from the origin, and the outermost radius where
// it falls through `level` (NaN: half way between its peak and the ambient value 1).
double shockRadius(const Solver& s, double dr, double rmax, double level, std::vector<double>* rr = nullptr, std::vector<double>* rho_out = nullptr) {
  const Grid& g = s.grid();
  const int nb = static_cast<int>(rmax / dr) + 1;
  std::vector<double> sum(static_cast<std::size_t>(nb), 0.0), wsum(static_cast<std::size_t>(nb), 0.0);
  for (int i = 0; i < g.cells(0); ++i)
    for (int j = 0; j < g.cells(1); ++j)
      for (int k = 0; k < g.cells(2); ++k) {
        const double x = g.centre(0, i), y = g.dims() > 1 ? g.centre(1, j) : 0.0, z = g.dims() > 2 ? g.centre(2, k) : 0.0;
        const double r = std::sqrt(x * x + y * y + z * z);
        const int b = static_cast<int>(r / dr);
        if (b >= nb) continue;
        const double v = g.cellVolume(i, j, k);
        sum[static_cast<std::size_t>(b)] += v * s.density(g.index(i, j, k));
        wsum[static_cast<std::size_t>(b)] += v;
      }
  std::vector<double> prof(static_cast<std::size_t>(nb), 1.0);
  double peak = 0.0;
  for (std::size_t b = 0; b < prof.size(); ++b) {
    if (wsum[b] > 0.0) prof[b] = sum[b] / wsum[b];
    peak = std::max(peak, prof[b]);
    if (rr && wsum[b] > 0.0) {
      rr->push_back((static_cast<double>(b) + 0.5) * dr);
      rho_out->push_back(prof[b]);
    }
  }
  const double half = std::isnan(level) ? 0.5 * (peak + 1.0) : level;
  for (int b = nb - 2; b >= 0; --b) {
    const double a = prof[static_cast<std::size_t>(b)], c = prof[static_cast<std::size_t>(b + 1)];
    if (a >= half && c < half) return (b + 0.5 + (a - half) / (a - c)) * dr;
  }
  return 0.0;
}

// Sedov's point blast, gamma = 1.4, rho = 1, shock at R = 1 at t = 1: cylindrical in a 2D plane
// quarter, spherical in a 2D axisymmetric half plane and a 3D octant.
void sedov(const std::string& variant, const std::vector<int>& levels, Report& rep) {
  const std::size_t first = rep.rows.size();
  const std::string name = "sedov-" + variant;
  for (const int n : levels) {
    const auto t0 = std::chrono::steady_clock::now();
    const double L = 1.2;
    int dims = 2;
    Geometry geo = Geometry::Cartesian;
    double energy = 0.0;   // J in the modelled part of the domain
    int nu = 3;
    if (variant == "cyl") {
      nu = 2;
      energy = sedovAlpha(2) / 4.0;
    } else if (variant == "axi") {
      geo = Geometry::Axisymmetric;
      energy = sedovAlpha(3) / (4.0 * M_PI);
    } else if (variant == "sph") {   // per steradian
      dims = 1;
      geo = Geometry::Spherical;
      energy = sedovAlpha(3) / (4.0 * M_PI);
    } else {
      dims = 3;
      energy = sedovAlpha(3) / 8.0;
    }
    std::array<Axis, 3> ax{Axis::uniform(0.0, L, n), Axis::uniform(0.0, L, n), Axis::uniform(0.0, L, dims == 3 ? n : 1)};
    SolverOptions o;
    setAll(o, BoundaryKind::Transmit);
    for (int d = 0; d < dims; ++d) o.boundary[static_cast<std::size_t>(d)][0] = BoundaryKind::Reflect;
    o.initial_dt_fraction = 1e-3;
    Solver s(Grid(dims, geo, ax), {materials::idealGas("gas", 1.4)}, o);
    s.paint(0, [](const Vec3&) { return true; }, 1.0, gasEnergy(1e-6, 1.0, 1.4));
    // Deposit the energy uniformly (per unit volume) in the cells within r = 0.05 of the origin: a
    // fixed physical radius (at least two cells) keeps the hot core's sound speed, and so the step
    // count, proportional to the resolution; its mass (< 0.3% of the swept mass) barely moves R.
    const Grid& g = s.grid();
    const double h = L / n, r_dep = std::max(0.05, 2.01 * h);
    double vol = 0.0;
    std::vector<std::size_t> hot;
    const int reach = static_cast<int>(r_dep / h) + 2;
    for (int i = 0; i < reach; ++i)
      for (int j = 0; j < (dims >= 2 ? reach : 1); ++j)
        for (int k = 0; k < (dims == 3 ? reach : 1); ++k) {
          const double x = g.centre(0, i), y = dims >= 2 ? g.centre(1, j) : 0.0, z = dims == 3 ? g.centre(2, k) : 0.0;
          if (x * x + y * y + z * z > r_dep * r_dep) continue;
          vol += g.cellVolume(i, j, k);
          hot.push_back(g.index(i, j, k));
        }
    for (const auto c : hot) s.setSpecificEnergy(0, c, energy / vol);   // rho = 1
    const auto before = s.totals();
    s.advanceTo(1.0);
    const auto after = s.totals();
    Profile prof{name, n, "r", "density (binned by radius)", {}, {}, {}};
    // The shock is where the radially binned density crosses the middle of the strong shock's
    // Rankine-Hugoniot jump, rho0 -> rho0 (gamma + 1) / (gamma - 1): the middle of a smeared
    // discontinuity. (Half of the numerical peak, which a coarse grid cuts well below the exact
    // post-shock density, puts the front about a cell ahead.) A profile too coarse to reach the
    // middle of the jump falls back to half its own peak.
    const double rh_middle = 0.5 * (1.0 + 2.4 / 0.4);
    double R = shockRadius(s, h, L, rh_middle, &prof.x, &prof.numeric);
    if (R == 0.0) R = shockRadius(s, h, L, kNaN);
    const double r_exact = sedovRadius(nu, energy * (nu == 2 ? 4.0 : (dims == 3 ? 8.0 : 4.0 * M_PI)), 1.0, 1.0);
    for (const double x : prof.x) prof.exact.push_back(x < r_exact ? kNaN : 1.0);
    rep.profiles.push_back(std::move(prof));
    rep.rows.push_back({name, dims == 3 ? "3D" : (geo == Geometry::Axisymmetric ? "2D axisymmetric" : (dims == 1 ? "1D spherical" : "2D plane")),
                        "|R_shock - R_exact| / R_exact", n, g.interiorCells(), std::abs(R - r_exact) / r_exact, 0.0,
                        drift(before, after), seconds(t0), "", true, s.stats().steps});
  }
  fillOrders(rep.rows, first, name);
  auto& last = rep.rows.back();
  const double tol = 0.01;
  last.check = fmt::format("shock radius within {:g}%", 100.0 * tol);
  last.passed = last.error <= tol;
}

// Noh's implosion, cylindrical (2D plane quarter), gamma = 5/3, t = 0.6: L1 density error inside
// r < 0.5 (away from the outer boundary's influence).
void noh(const std::vector<int>& levels, Report& rep) {
  const std::size_t first = rep.rows.size();
  for (const int n : levels) {
    const auto t0 = std::chrono::steady_clock::now();
    const double L = 1.2, t_end = 0.6;
    std::array<Axis, 3> ax{Axis::uniform(0.0, L, n), Axis::uniform(0.0, L, n), Axis::uniform(0.0, 1.0, 1)};
    SolverOptions o;
    setAll(o, BoundaryKind::Transmit);
    o.boundary[0][0] = o.boundary[1][0] = BoundaryKind::Reflect;
    Solver s(Grid(2, Geometry::Cartesian, ax), {materials::idealGas("gas", 5.0 / 3.0)}, o);
    s.paint(0, [](const Vec3&) { return true; }, 1.0, gasEnergy(1e-6, 1.0, 5.0 / 3.0));
    const Grid& g = s.grid();
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double x = g.centre(0, i), y = g.centre(1, j), r = std::hypot(x, y);
        s.setVelocity(g.index(i, j, 0), {-x / r, -y / r, 0.0});
      }
    const auto before = s.totals();
    s.advanceTo(t_end);
    const auto after = s.totals();
    double l1 = 0.0, area = 0.0;
    Profile prof{"noh", n, "r (along the diagonal)", "density", {}, {}, {}};
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double x = g.centre(0, i), y = g.centre(1, j), r = std::hypot(x, y);
        if (r >= 0.5) continue;
        const double v = g.cellVolume(i, j, 0);
        l1 += v * std::abs(s.density(g.index(i, j, 0)) - nohDensity(r, t_end));
        area += v;
        if (i == j) {
          prof.x.push_back(r);
          prof.numeric.push_back(s.density(g.index(i, j, 0)));
          prof.exact.push_back(nohDensity(r, t_end));
        }
      }
    rep.profiles.push_back(std::move(prof));
    // the shock radius where the binned density crosses the middle of the jump 4 -> 16
    const double R = shockRadius(s, L / n, 0.5, 10.0), r_exact = t_end / 3.0;
    rep.rows.push_back({"noh", "2D plane", "|R_shock - R_exact| / R_exact", n, g.interiorCells(), std::abs(R - r_exact) / r_exact, 0.0,
                        drift(before, after), seconds(t0), "", true, s.stats().steps});
    rep.rows.push_back({"noh-L1", "2D plane", "L1(density), r < 0.5", n, g.interiorCells(), l1 / area, kNaN, kNaN, 0.0, "", true});
  }
  fillOrders(rep.rows, first, "noh");
  fillOrders(rep.rows, first, "noh-L1");
  // Checked at the finest level: the shock radius within 2%, and the L1 density error below 0.25
  // (a limit set by the axis anomalies below; it catches a scheme that smears or misplaces the shock).
  for (auto it = rep.rows.rbegin(); it != rep.rows.rend(); ++it)
    if (it->problem == "noh") {
      it->check = "shock radius within 2%";
      it->passed = it->error <= 0.02;
      break;
    }
  for (auto it = rep.rows.rbegin(); it != rep.rows.rend(); ++it)
    if (it->problem == "noh-L1") {
      it->check = "L1(density) <= 0.25";
      it->passed = it->error <= 0.25;
      break;
    }
  // Informative: on a Cartesian grid the reflecting axes carry the known Noh anomalies (noise and
  // jetting along the axes) that stall convergence at these resolutions; see docs/solver.md.
}

// A heavy disc carried diagonally through a periodic box by a uniform flow, then back: material
// masses (held plus folded, Solver's fragments) must be kept to round-off and the shape kept sharp.
void interfaceAdvection(const std::vector<int>& levels, Report& rep) {
  const std::size_t first = rep.rows.size();
  std::size_t last_shape = first;
  for (const int n : levels) {
    const auto t0 = std::chrono::steady_clock::now();
    std::array<Axis, 3> ax{Axis::uniform(0.0, 1.0, n), Axis::uniform(0.0, 1.0, n), Axis::uniform(0.0, 1.0, 1)};
    SolverOptions o;
    setAll(o, BoundaryKind::Periodic);
    Solver s(Grid(2, Geometry::Cartesian, ax), {materials::idealGas("light", 1.4), materials::idealGas("heavy", 5.0 / 3.0)}, o);
    s.paint(0, [](const Vec3&) { return true; }, 1.0, gasEnergy(1.0, 1.0, 1.4), {1.0, 0.5, 0.0});
    auto disc = [](const Vec3& x) { return std::hypot(x[0] - 0.3, x[1] - 0.3) < 0.15; };
    s.paint(1, disc, 10.0, gasEnergy(1.0, 10.0, 5.0 / 3.0), {1.0, 0.5, 0.0}, 8);
    const Grid& g = s.grid();
    std::vector<double> a0(g.totalCells());
    for (std::size_t c = 0; c < a0.size(); ++c) a0[c] = s.field(1).alpha[c];
    const auto before = s.totals();
    s.advanceTo(0.5);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const std::size_t c = g.index(i, j, 0);
        s.setVelocity(c, {-s.velocity(0)[c], -s.velocity(1)[c], 0.0});
      }
    s.advanceTo(1.0);
    const auto after = s.totals();
    double shape = 0.0, vol0 = 0.0, vol1 = 0.0;
    Profile prof{"interface", n, "x (along y = 0.3)", "heavy-material volume fraction", {}, {}, {}};
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const std::size_t c = g.index(i, j, 0);
        const double v = g.cellVolume(i, j, 0);
        shape += v * std::abs(s.field(1).alpha[c] - a0[c]);
        vol0 += v * a0[c];
        vol1 += v * s.field(1).alpha[c];
        if (j == cellAt(g, 1, 0.3)) {
          prof.x.push_back(g.centre(0, i));
          prof.numeric.push_back(s.field(1).alpha[c]);
          prof.exact.push_back(a0[c]);
        }
      }
    rep.profiles.push_back(std::move(prof));
    Row row{"interface", "2D plane", "L1(volume fraction) / disc area", n, g.interiorCells(), shape / vol0, 0.0, drift(before, after),
            seconds(t0), "", true, s.stats().steps};
    last_shape = rep.rows.size();
    rep.rows.push_back(row);
    double mass_drift = 0.0, folded = 0.0;
    for (std::size_t k = 0; k < 2; ++k) {
      mass_drift = std::max(mass_drift, std::abs(after.mass[k] + after.folded_mass[k] - before.mass[k]) / before.mass[k]);
      folded = std::max(folded, std::abs(after.folded_mass[k]) / before.mass[k]);
    }
    rep.rows.push_back({"interface-mass", "2D plane", "max relative change of a material's mass, held + folded into the other", n, g.interiorCells(),
                        mass_drift, kNaN, mass_drift, 0.0, "<= 1e-12", mass_drift <= 1e-12});
    rep.rows.push_back({"interface-folded", "2D plane", "max share of a material's mass folded into the other (fragments)", n, g.interiorCells(),
                        folded, kNaN, mass_drift, 0.0, "", false});
    rep.rows.push_back({"interface-volume", "2D plane", "relative change of the disc's volume", n, g.interiorCells(),
                        std::abs(vol1 - vol0) / vol0, kNaN, mass_drift, 0.0, "<= 1e-3", std::abs(vol1 - vol0) / vol0 <= 1e-3});
  }
  fillOrders(rep.rows, first, "interface");   // orders on the shape rows only
  auto& last = rep.rows[last_shape];
  last.check = "shape error <= 6% (sharp interface)";
  last.passed = last.error <= 0.06;
}

// A planar detonation run from a rigid wall through a slab of explosive (programmed burn): the
// peak pressure against the handbook CJ pressure and the pressure profile against the Taylor wave.
void jwlDetonation(const std::string& explosive, const std::vector<int>& levels, Report& rep) {
  const std::size_t first = rep.rows.size();
  const Material mat = materials::explosive(explosive);
  const TaylorWave wave(mat.jwl);
  const double L = 0.1, t_end = 0.08 / mat.jwl.d_cj;
  const std::string name = "jwl-" + explosive;
  for (const int n : levels) {
    const auto t0 = std::chrono::steady_clock::now();
    SolverOptions o;
    setAll(o, BoundaryKind::Transmit);
    o.boundary[0][0] = BoundaryKind::Reflect;
    o.detonation.push_back({{0.0, 0.0, 0.0}, 0.0});
    Solver s(Grid(1, Geometry::Cartesian, {Axis::uniform(0.0, L, n), Axis{}, Axis{}}), {mat}, o);
    s.paint(0, [](const Vec3&) { return true; }, mat.jwl.rho0, mat.jwl.e0 / mat.jwl.rho0);
    const auto before = s.totals();
    s.advanceTo(t_end);
    const auto after = s.totals();
    const Grid& g = s.grid();
    double peak = 0.0, l1 = 0.0;
    const double front = mat.jwl.d_cj * t_end;
    Profile prof{name, n, "x [m]", "pressure [Pa]", {}, {}, {}};
    for (int i = 0; i < n; ++i) {
      const double x = g.centre(0, i);
      const double p = s.pressure(g.index(i, 0, 0));
      const double ex = x < front ? wave.pressure(x / t_end) : 0.0;
      peak = std::max(peak, p);
      if (x < 0.9 * front) l1 += std::abs(p - ex) * (L / n);
      prof.x.push_back(x);
      prof.numeric.push_back(p);
      prof.exact.push_back(ex);
    }
    rep.profiles.push_back(std::move(prof));
    rep.rows.push_back({name, "1D", "L1(p) behind the front / (p_CJ x_front)", n, g.interiorCells(), l1 / (wave.cj().pressure * 0.9 * front), 0.0,
                        drift(before, after), seconds(t0), "", true, s.stats().steps});
    rep.rows.push_back({name + "-peak", "1D", "|p_peak - p_CJ(handbook)| / p_CJ", n, g.interiorCells(),
                        std::abs(peak - mat.jwl.p_cj) / mat.jwl.p_cj, kNaN, drift(before, after), 0.0, "", true});
  }
  fillOrders(rep.rows, first, name);
  auto& last = rep.rows.back();
  last.check = "peak within 2% of the handbook CJ pressure";
  last.passed = last.error <= 0.02;
  const auto cj = wave.cj();
  rep.rows.push_back({name + "-eos", "-", "|p_CJ(JWL constants) - p_CJ(handbook)| / p_CJ", 0, 0, std::abs(cj.pressure - mat.jwl.p_cj) / mat.jwl.p_cj,
                      kNaN, 0.0, 0.0, "", true});
}

// A 40 mm slab of Comp B detonated at a rigid wall and expanding into air (1D): the products should
// follow the CJ isentrope. Reported over the cells of pure products at 100 us (V = 10 to 50): the
// mass-weighted mean of E / E_s(V) - 1, and the energy they hold over what the isentrope gives at
// their volumes, sum m E / sum m E_s(V) - 1 (`-energy`): the entropy the burn, the wall, the
// products-air contact and the remap add, which at coarse cells drives the products' late pressure
// (docs/solver.md). No tracking of any kind. Informative: the aim (within 5% at 20 cells
// per slab) is not met yet (docs/solver.md says where the excess sits: the tenth of the mass
// nearest the air converges at about half order, the tenth at the wall at 0.5-0.85, the rest at second).
void productsIsentrope(const std::vector<int>& levels, Report& rep) {
  const std::string name = "products-isentrope";
  const std::size_t first = rep.rows.size();
  const Material ex = materials::explosive("CompB");
  const materials::JwlIsentrope isentrope(ex.jwl);
  const double slab = 0.04, L = 2.0, t_end = 100e-6;
  for (const int n : levels) {
    const auto t0 = std::chrono::steady_clock::now();
    const int cells = static_cast<int>(std::lround(L / slab * n));
    SolverOptions o;
    setAll(o, BoundaryKind::Transmit);
    o.boundary[0][0] = BoundaryKind::Reflect;
    o.detonation.push_back({{0.0, 0.0, 0.0}, 0.0});
    Solver s(Grid(1, Geometry::Cartesian, {Axis::uniform(0.0, L, cells), Axis{}, Axis{}}), {materials::air(), ex}, o);
    s.paint(0, [](const Vec3&) { return true; }, 1.225, gasEnergy(101325.0, 1.225, 1.4));
    s.paint(1, [slab](const Vec3& x) { return x[0] < slab; }, ex.jwl.rho0, ex.jwl.e0 / ex.jwl.rho0, {}, 8);
    const auto before = s.totals();
    s.advanceTo(t_end);
    const auto after = s.totals();
    const Grid& g = s.grid();
    const auto& F = s.field(1);
    double mass = 0.0, excess = 0.0, e_held = 0.0, e_isen = 0.0;
    Profile prof{name, n, "relative volume V = rho0/rho", "E / E_s(V) (pure products cells)", {}, {}, {}};
    for (int i = 0; i < cells; ++i) {
      const std::size_t c = g.index(i, 0, 0);
      if (F.alpha[c] < 0.99) continue;
      const double V = ex.jwl.rho0 / F.rho[c], m = F.rho[c] * g.cellVolume(i, 0, 0);
      const double Es = isentrope.energy(V), ratio = ex.jwl.rho0 * F.e[c] / Es;
      mass += m;
      excess += m * (ratio - 1.0);
      e_held += m * F.e[c];
      e_isen += m * Es / ex.jwl.rho0;
      prof.x.push_back(V);
      prof.numeric.push_back(ratio);
      prof.exact.push_back(1.0);
    }
    rep.profiles.push_back(std::move(prof));
    const double err = mass > 0.0 ? excess / mass : kNaN;
    rep.rows.push_back({name, "1D", "mass mean of E/E_s(V) - 1, CompB products at 100 us", n, g.interiorCells(), err, 0.0,
                        drift(before, after), seconds(t0), "", false, s.stats().steps});
    rep.rows.push_back({name + "-energy", "1D", "sum m E / sum m E_s(V) - 1, CompB products at 100 us", n, g.interiorCells(),
                        e_isen > 0.0 ? e_held / e_isen - 1.0 : kNaN, 0.0, drift(before, after), 0.0, "", false});
  }
  fillOrders(rep.rows, first, name);
  fillOrders(rep.rows, first, name + "-energy");
}

// A 40 mm slab of Comp B detonated at a rigid wall, driving EMI sand at 22% moisture (1D planar):
// each material's total energy (internal + kinetic) and the sand's momentum as histories, sampled
// every 2 us to 100 us, against the same code at 8x finer cells than the finest level. The error is
// the history's L1 norm relative to the reference's, sum |q - q_ref| / sum |q_ref| over the 50
// times: an error at a few chosen times passes through zero when two error components of opposite
// sign trade places (the sand's momentum: the slower early drive, negative, and the products'
// excess energy later, positive, cross near 100 us), and its pointwise order then says nothing.
// The order fitted over the levels must be >= 0.9 (the scheme's first order at shocks and contacts).
void chargeInWetSand(const std::vector<int>& levels, Report& rep) {
  const Material ex = materials::explosive("CompB");
  const Material sand = materials::sand(materials::SandInputs::fromWetDensity(1370.0 / 1.07 * 1.22, 0.22), "sand");
  // the sand's shock is at 0.28 m at 100 us: the far boundary at 0.4 m is never reached
  const double slab = 0.04, L = 0.4;
  constexpr int kSamples = 50;
  constexpr double kSampleEvery_s = 2e-6;
  struct Sample { double products, sand, momentum; };
  auto simulate = [&](int n, std::size_t* cells, long long* steps, double* books) {
    const int nc = static_cast<int>(std::lround(L / slab * n));
    SolverOptions o;
    setAll(o, BoundaryKind::Transmit);
    o.boundary[0][0] = BoundaryKind::Reflect;
    o.detonation.push_back({{0.0, 0.0, 0.0}, 0.0});
    Solver s(Grid(1, Geometry::Cartesian, {Axis::uniform(0.0, L, nc), Axis{}, Axis{}}), {ex, sand}, o);
    s.paint(1, [](const Vec3&) { return true; }, sand.referenceDensity(), 0.0);
    s.paint(0, [slab](const Vec3& x) { return x[0] < slab; }, ex.jwl.rho0, ex.jwl.e0 / ex.jwl.rho0, {}, 8);
    const auto before = s.totals();
    std::vector<Sample> out;
    for (int q = 1; q <= kSamples; ++q) {
      s.advanceTo(q * kSampleEvery_s);
      const auto tt = s.totals();
      const Grid& g = s.grid();
      double mom = 0.0;
      for (int i = 0; i < g.cells(0); ++i) {
        const std::size_t c = g.index(i, 0, 0);
        mom += s.field(1).alpha[c] * s.field(1).rho[c] * g.cellVolume(i, 0, 0) * s.velocity(0)[c];
      }
      out.push_back({tt.internal_by_material[0] + tt.kinetic_by_material[0], tt.internal_by_material[1] + tt.kinetic_by_material[1], mom});
    }
    *cells = s.grid().interiorCells();
    *steps = s.stats().steps;
    *books = drift(before, s.totals());
    return out;
  };
  std::size_t cells = 0;
  long long steps = 0;
  double books = 0.0;
  const int ref_n = 8 * levels.back();
  const auto ref = simulate(ref_n, &cells, &steps, &books);
  const char* names[] = {"wet-sand-products-energy", "wet-sand-sand-energy", "wet-sand-sand-momentum"};
  const char* metrics[] = {"sum |E_products - E_ref| / sum |E_ref|, every 2 us to 100 us", "sum |E_sand - E_ref| / sum |E_ref|, every 2 us to 100 us",
                           "sum |P_sand - P_ref| / sum |P_ref|, every 2 us to 100 us"};
  std::vector<std::size_t> first(3, rep.rows.size());
  for (const int n : levels) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto got = simulate(n, &cells, &steps, &books);
    const double secs = seconds(t0);
    for (int q = 0; q < 3; ++q) {
      double diff = 0.0, norm = 0.0;
      for (std::size_t i = 0; i < got.size(); ++i) {
        const double a = q == 0 ? got[i].products : (q == 1 ? got[i].sand : got[i].momentum);
        const double b = q == 0 ? ref[i].products : (q == 1 ? ref[i].sand : ref[i].momentum);
        diff += std::abs(a - b);
        norm += std::abs(b);
      }
      const double err = diff / norm;
      rep.rows.push_back({names[q], "1D", metrics[q], n, cells, err, 0.0, books, q == 0 ? secs : 0.0,
                          "", false, steps});
    }
  }
  // The order is judged by a least-squares fit of log(error) against log(cells) over every level
  // (one pair of levels can be pre-asymptotic or cancel between the sampled times); the order
  // column keeps the pairwise values.
  for (int q = 0; q < 3; ++q) {
    fillOrders(rep.rows, first[static_cast<std::size_t>(q)], names[q]);
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, nn = 0.0;
    Row* last = nullptr;
    for (std::size_t r = first[static_cast<std::size_t>(q)]; r < rep.rows.size(); ++r) {
      if (rep.rows[r].problem != names[q] || !(rep.rows[r].error > 0.0)) continue;
      const double x = std::log(static_cast<double>(rep.rows[r].resolution)), y = std::log(rep.rows[r].error);
      sx += x;
      sy += y;
      sxx += x * x;
      sxy += x * y;
      nn += 1.0;
      last = &rep.rows[r];
    }
    if (!last) continue;
    const double fit = nn > 1.0 ? -(nn * sxy - sx * sy) / (nn * sxx - sx * sx) : kNaN;
    last->check = fmt::format("fitted order over {}-{} cells per slab >= 0.9 (reference: {} cells per slab): {:.2f}", levels.front(), levels.back(), ref_n, fit);
    last->passed = fit >= 0.9;
  }
}

// Position of the last crossing (from the high side of the axis) of `level` by `field`.
double frontPosition(const std::vector<double>& x, const std::vector<double>& f, double level) {
  for (std::size_t i = x.size() - 1; i > 0; --i)
    if ((f[i] - level) * (f[i - 1] - level) <= 0.0 && f[i] != f[i - 1]) return x[i - 1] + (level - f[i - 1]) / (f[i] - f[i - 1]) * (x[i] - x[i - 1]);
  return kNaN;
}

// Axial stress (compression positive) of the cells along a 1D line.
std::vector<double> axialStress(const Solver& s) {
  std::vector<double> out;
  const Grid& g = s.grid();
  for (int i = 0; i < g.cells(0); ++i) {
    const std::size_t c = g.index(i, 0, 0);
    double sig = 0.0;
    for (int k = 0; k < s.materialCount(); ++k) {
      const auto& f = s.field(k);
      sig += f.alpha[c] * (s.materialPressure(k, c) - (f.s[0].empty() ? 0.0 : f.s[0][c]));
    }
    out.push_back(sig);
  }
  return out;
}

// Sand driven against a rigid wall at 200 m/s (the piston problem in the piston's frame): the
// shock speed against the Rankine-Hugoniot jump of the loading curve with plastic strength.
void sandPiston(const std::vector<int>& levels, Report& rep) {
  const std::size_t first = rep.rows.size();
  const Material sand = materials::sand(materials::SandInputs::fromWetDensity(1370.0, 0.07), "EMI 7% sand");
  const double up = 200.0, L = 0.4;
  const SandShock rh = sandPistonShock(sand, up);
  const double t1 = 0.3 * L / (rh.shock_speed - up), t2 = 0.8 * L / (rh.shock_speed - up);
  for (const int n : levels) {
    const auto t0 = std::chrono::steady_clock::now();
    SolverOptions o;
    setAll(o, BoundaryKind::Transmit);
    o.boundary[0][0] = BoundaryKind::Reflect;
    Solver s(Grid(1, Geometry::Cartesian, {Axis::uniform(0.0, L, n), Axis{}, Axis{}}), {sand}, o);
    s.paint(0, [](const Vec3&) { return true; }, sand.referenceDensity(), 0.0, {-up, 0.0, 0.0});
    std::vector<double> x;
    for (int i = 0; i < n; ++i) x.push_back(s.grid().centre(0, i));
    auto front = [&]() {
      const auto sig = axialStress(s);
      return frontPosition(x, sig, 0.5 * rh.stress);
    };
    s.advanceTo(t1);
    const double x1 = front();
    s.advanceTo(t2);
    const double x2 = front();
    const double us = (x2 - x1) / (t2 - t1) + up;
    const auto sig = axialStress(s);
    Profile prof{"sand-piston", n, "x [m]", "axial stress [Pa]", x, sig, {}};
    for (const double xi : x) prof.exact.push_back(xi < (rh.shock_speed - up) * t2 ? rh.stress : 0.0);
    rep.profiles.push_back(std::move(prof));
    rep.rows.push_back({"sand-piston", "1D", "|U_shock - U_RH| / U_RH", n, s.grid().interiorCells(), std::abs(us - rh.shock_speed) / rh.shock_speed,
                        0.0, kNaN, seconds(t0), "", true, s.stats().steps});
  }
  fillOrders(rep.rows, first, "sand-piston");
  auto& last = rep.rows.back();
  last.check = "shock speed within 2%";
  last.passed = last.error <= 0.02;
}

// Steel driven against a rigid wall at 100 m/s: the elastic precursor's amplitude against the
// Hugoniot elastic limit and its speed against the longitudinal wave speed.
void steelPrecursor(const std::vector<int>& levels, Report& rep) {
  const std::size_t first = rep.rows.size();
  const Material steel = materials::steel();
  const ElasticPrecursor ep = elasticPrecursor(steel);
  const double up = 100.0, L = 0.1, t_end = 0.8 * L / ep.speed;
  for (const int n : levels) {
    const auto t0 = std::chrono::steady_clock::now();
    SolverOptions o;
    setAll(o, BoundaryKind::Transmit);
    o.boundary[0][0] = BoundaryKind::Reflect;
    Solver s(Grid(1, Geometry::Cartesian, {Axis::uniform(0.0, L, n), Axis{}, Axis{}}), {steel}, o);
    s.paint(0, [](const Vec3&) { return true; }, steel.referenceDensity(), 0.0, {-up, 0.0, 0.0});
    s.advanceTo(t_end);
    std::vector<double> x;
    for (int i = 0; i < n; ++i) x.push_back(s.grid().centre(0, i));
    const auto sig = axialStress(s);
    const double x_el = frontPosition(x, sig, 0.5 * ep.hel);
    // the plateau between the plastic front and the precursor: sample the middle third of it
    const double x_pl = frontPosition(x, sig, 0.5 * (ep.hel + sig.front()));
    double sum = 0.0;
    int cnt = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (x[i] > x_pl + (x_el - x_pl) / 3.0 && x[i] < x_el - (x_el - x_pl) / 3.0) {
        sum += sig[i];
        ++cnt;
      }
    const double plateau = cnt ? sum / cnt : kNaN;
    Profile prof{"steel-precursor", n, "x [m]", "axial stress [Pa]", x, sig, {}};
    for (const double xi : x) prof.exact.push_back(xi > x_pl && xi < (ep.speed - up) * t_end ? ep.hel : kNaN);
    rep.profiles.push_back(std::move(prof));
    const double speed = x_el / t_end + up;
    rep.rows.push_back({"steel-precursor", "1D", "|sigma_plateau - HEL| / HEL", n, s.grid().interiorCells(), std::abs(plateau - ep.hel) / ep.hel, 0.0,
                        kNaN, seconds(t0), "", true, s.stats().steps});
    rep.rows.push_back({"steel-precursor-speed", "1D", "|c_precursor - c_L| / c_L", n, s.grid().interiorCells(), std::abs(speed - ep.speed) / ep.speed,
                        kNaN, kNaN, 0.0, "", true});
  }
  fillOrders(rep.rows, first, "steel-precursor");
  for (std::size_t r = rep.rows.size() - 2; r < rep.rows.size(); ++r) {
    rep.rows[r].check = "within 3%";
    rep.rows[r].passed = rep.rows[r].error <= 0.03;
  }
}

// 1 kg TNT sphere in free air, 1D spherical, run as `ejecta run` runs a charge (RunSettings): the
// deck's air and JWL, CFL, centre initiation, the charge painted with sub-samples, the first step a
// fraction of the CFL step and growing by at most 20% a step, and, where the run's cells give the
// charge fewer than 20 per height (diameter), the early time on a nested fine block mapped onto the
// run mesh (hydro::mapNested) when the fastest wave could reach the block's cut side. Peak incident
// overpressure at 1, 1.5, 2 and 3 m (linear between cell centres, the largest over every step).
struct FreeAirRun {
  std::vector<double> peaks;   // Pa over ambient, per gauge
  std::size_t cells = 0;
  long long steps = 0;         // run mesh and fine block together
  double books = 0.0;
  double fine_cell_m = 0.0;    // the early-time block's cell (0: not used)
};
FreeAirRun tntFreeAirRun(double cell_m, const std::vector<double>& gauges, double mass) {
  const RunSettings rs;
  const Material air = materials::air(), tnt = materials::explosive("TNT");
  const double radius = std::cbrt(3.0 * mass / (4.0 * M_PI * tnt.jwl.rho0)), height = 2.0 * radius;
  const double p0 = rs.air_pressure_pa, rho_air = rs.air_density_kg_m3;
  const double L = gauges.back() + 0.5;   // room for the front to pass the last gauge before any outflow matters
  const int n = static_cast<int>(std::lround(L / cell_m));
  SolverOptions o;
  o.cfl = rs.cfl;
  o.initial_dt_fraction = rs.initial_dt_fraction;
  o.boundary[0] = {BoundaryKind::Reflect, BoundaryKind::Transmit};
  o.detonation.push_back({{0.0, 0.0, 0.0}, 0.0});
  auto paintCharge = [&](Solver& s) {
    s.paint(0, [](const Vec3&) { return true; }, rho_air, gasEnergy(p0, rho_air, 1.4));
    s.paint(1, [radius](const Vec3& x) { return std::abs(x[0]) < radius; }, tnt.jwl.rho0, tnt.jwl.e0 / tnt.jwl.rho0, {}, rs.charge_paint_samples);
  };
  Solver s(Grid(1, Geometry::Spherical, {Axis::uniform(0.0, L, n), Axis{}, Axis{}}), {air, tnt}, o);
  paintCharge(s);
  double e_initial = s.totals().total();
  FreeAirRun out;
  out.cells = s.grid().interiorCells();
  const double h = L / n;
  if (h * rs.early_cells_per_charge_height > height * (1.0 + 1e-9)) {
    const int ratio = static_cast<int>(std::ceil(h * rs.early_cells_per_charge_height / height - 1e-9));
    const double burn_time = std::hypot(radius, height) / tnt.jwl.d_cj;   // as scenario::planEarly, for a charge of this height
    const int run_cells = static_cast<int>(std::ceil((radius + rs.early_reach_burn_times * burn_time * rs.early_signal_speed_m_s) / h - 1e-9));
    const double r_block = run_cells * h;
    Solver fine(Grid(1, Geometry::Spherical, {Axis::uniform(0.0, r_block, run_cells * ratio), Axis{}, Axis{}}), {air, tnt}, o);
    paintCharge(fine);
    const double e_fine0 = fine.totals().total();
    fine.advanceTo((r_block - radius) / rs.early_signal_speed_m_s);   // Solver::advanceTo grows the step as the run's early loop does
    const auto fine_tot = fine.totals();
    hydro::mapNested(fine, s);
    s.startAt(fine.time(), fine.energyLedger());
    e_initial = s.totals().total() - fine_tot.total() + e_fine0;
    out.steps += fine.stats().steps;
    out.fine_cell_m = r_block / (run_cells * ratio);
  }
  const Grid& g = s.grid();
  std::vector<std::pair<int, double>> at;   // the cell below each gauge and the weight of the one above
  for (const double r : gauges) {
    const int i = std::clamp(static_cast<int>(std::floor(r / h - 0.5)), 0, n - 2);
    at.push_back({i, (r - g.centre(0, i)) / (g.centre(0, i + 1) - g.centre(0, i))});
  }
  out.peaks.assign(gauges.size(), 0.0);
  const double front_level = 0.01 * kinneyGrahamOverpressure(gauges.back() / std::cbrt(mass), p0);
  auto frontRadius = [&]() {
    for (int i = n - 1; i >= 0; --i)
      if (s.pressure(g.index(i, 0, 0)) - p0 > front_level) return g.centre(0, i);
    return 0.0;
  };
  // Steps as run.cpp's main loop (no output times to land on) until the front is well past the last gauge.
  double dt_prev = 0.0;
  while (frontRadius() < gauges.back() + 0.2) {
    if (s.time() > 0.05) throw RunError("tnt-free-air: the blast front did not pass the last gauge within 50 ms");
    double dt = s.stableTimeStep();
    dt = dt_prev > 0.0 ? std::min(dt, rs.dt_growth * dt_prev) : rs.initial_dt_fraction * dt;
    s.step(dt);
    dt_prev = dt;
    for (std::size_t q = 0; q < gauges.size(); ++q) {
      const double pl = s.pressure(g.index(at[q].first, 0, 0)), pr = s.pressure(g.index(at[q].first + 1, 0, 0));
      out.peaks[q] = std::max(out.peaks[q], pl + at[q].second * (pr - pl) - p0);
    }
  }
  out.steps += s.stats().steps;
  const auto end = s.totals();
  out.books = std::abs(end.total() - end.accounted(e_initial)) / std::max(std::abs(e_initial), std::abs(end.total()));
  return out;
}

// Checked at the finest level: each gauge's peak within 20% of Kinney & Graham's curve (a fit to
// measurements; the published free-air curves differ from it by 10-25% at these distances, see
// docs/solver.md, so a converged ideal-gas air + JWL model can be asked for no more), and the peaks
// converged: no gauge's peak moves more than 5% between the two finest levels, so that what is
// compared with the curve is the model's answer and not the mesh's. The coarser levels are
// informative; the coarsest, 10 mm, is the run's own cell size with its early-time block.
void tntFreeAir(const std::vector<double>& cells_mm, Report& rep) {
  const double mass = 1.0, p0 = RunSettings{}.air_pressure_pa;
  const std::vector<double> gauges{1.0, 1.5, 2.0, 3.0};
  constexpr double kCurveLimit = 0.20, kConvergedLimit = 0.05;
  std::vector<double> ref;
  for (const double r : gauges) ref.push_back(kinneyGrahamOverpressure(r / std::cbrt(mass), p0));
  std::vector<std::vector<double>> peaks;
  for (const double mm : cells_mm) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto run = tntFreeAirRun(mm / 1000.0, gauges, mass);
    double worst = 0.0;
    std::string each;
    for (std::size_t q = 0; q < gauges.size(); ++q) {
      const double err = (run.peaks[q] - ref[q]) / ref[q];
      worst = std::max(worst, std::abs(err));
      each += fmt::format("{}{:g} m {:+.1f}%", q ? ", " : "", gauges[q], 100.0 * err);
    }
    const std::string early = run.fine_cell_m > 0.0 ? fmt::format(", early time on {:.3g} mm cells", 1e3 * run.fine_cell_m) : "";
    rep.rows.push_back({"tnt-free-air", "1D spherical", fmt::format("max |dp_peak - dp_KG| / dp_KG over 1-3 m ({:g} mm cells{}; {})", mm, early, each),
                        static_cast<int>(run.cells), run.cells, worst, kNaN, run.books, seconds(t0), "", true, run.steps});
    peaks.push_back(run.peaks);
  }
  const std::size_t cells = rep.rows.back().cells;
  Profile prof{"tnt-free-air", rep.rows.back().resolution, "distance [m] (1 kg TNT)", "peak overpressure [Pa]", gauges, peaks.back(), ref};
  rep.profiles.push_back(std::move(prof));
  for (std::size_t q = 0; q < gauges.size(); ++q) {
    const double err = std::abs(peaks.back()[q] - ref[q]) / ref[q];
    rep.rows.push_back({fmt::format("tnt-free-air@{:g}m", gauges[q]), "1D spherical",
                        fmt::format("|dp_peak - dp_KG| / dp_KG (Kinney & Graham 1985: {:.4g} kPa), {:g} mm cells", 1e-3 * ref[q], cells_mm.back()),
                        rep.rows.back().resolution, cells, err, kNaN, kNaN, 0.0, fmt::format("within {:g}% of the curve (the published curves' spread)", 100.0 * kCurveLimit),
                        err <= kCurveLimit});
  }
  if (peaks.size() >= 2) {
    double moved = 0.0;
    const auto& a = peaks[peaks.size() - 2];
    const auto& b = peaks.back();
    for (std::size_t q = 0; q < gauges.size(); ++q) moved = std::max(moved, std::abs(b[q] - a[q]) / b[q]);
    rep.rows.push_back({"tnt-free-air-converged", "1D spherical",
                        fmt::format("max over the gauges of |dp({:g} mm) - dp({:g} mm)| / dp({:g} mm)", cells_mm[cells_mm.size() - 2], cells_mm.back(),
                                    cells_mm.back()),
                        rep.rows.back().resolution, cells, moved, kNaN, kNaN, 0.0, fmt::format("<= {:g}% between the two finest levels (converged)", 100.0 * kConvergedLimit),
                        moved <= kConvergedLimit});
  }
}

}  // namespace

// A row with no check is informative and never counts as a pass.
bool Report::allPassed() const {
  return std::all_of(rows.begin(), rows.end(), [](const Row& r) { return r.check.empty() || r.passed; });
}

std::vector<std::string> problemGroups() {
  return {"sod", "advection", "sedov", "noh", "interface", "jwl", "products-isentrope", "wet-sand", "sand-piston", "steel-precursor", "tnt-free-air"};
}

Report runVerification(const Options& opt) {
  for (const auto& o : opt.only) {
    const auto groups = problemGroups();
    if (std::find(groups.begin(), groups.end(), o) == groups.end())
      throw InputError("--only", fmt::format("'{}' is not a problem; valid: {}", o, fmt::join(groups, ", ")));
  }
  auto wanted = [&](const std::string& g) { return opt.only.empty() || std::find(opt.only.begin(), opt.only.end(), g) != opt.only.end(); };
  auto say = [&](const std::string& m) {
    if (opt.log) opt.log(m);
  };
  const bool q = opt.quick;
  Report rep;
  if (wanted("sod")) {
    say("Sod shock tube along x, y and z");
    for (int axis = 0; axis < 3; ++axis) sod(axis, q ? std::vector<int>{100, 200, 400} : std::vector<int>{100, 200, 400, 800}, rep);
  }
  if (wanted("advection")) {
    say("smooth density wave, 1D and 2D diagonal");
    smoothAdvection(1, q ? std::vector<int>{32, 64, 128} : std::vector<int>{32, 64, 128, 256}, rep);
    smoothAdvection(2, q ? std::vector<int>{32, 64, 128} : std::vector<int>{32, 64, 128, 256}, rep);
  }
  if (wanted("sedov")) {
    say("Sedov blast: cylindrical (2D plane), spherical (2D axisymmetric, 3D, 1D spherical)");
    sedov("cyl", q ? std::vector<int>{60, 120, 240} : std::vector<int>{60, 120, 240, 480}, rep);
    sedov("axi", q ? std::vector<int>{60, 120, 240} : std::vector<int>{60, 120, 240, 480}, rep);
    sedov("3d", q ? std::vector<int>{24, 48} : std::vector<int>{24, 48, 96}, rep);
    sedov("sph", q ? std::vector<int>{60, 120, 240} : std::vector<int>{60, 120, 240, 480}, rep);
  }
  if (wanted("noh")) {
    say("Noh implosion (cylindrical)");
    noh(q ? std::vector<int>{60, 120, 240} : std::vector<int>{60, 120, 240, 480}, rep);
  }
  if (wanted("interface")) {
    say("two-material interface carried across the grid and back");
    interfaceAdvection(q ? std::vector<int>{64, 128} : std::vector<int>{64, 128, 256}, rep);
  }
  if (wanted("jwl")) {
    say("1D JWL detonations (C4, CompB, TNT)");
    for (const char* e : {"C4", "CompB", "TNT"}) jwlDetonation(e, q ? std::vector<int>{500, 1000, 2000, 4000} : std::vector<int>{500, 1000, 2000, 4000, 8000}, rep);
  }
  if (wanted("sand-piston")) {
    say("piston into EMI 7% sand");
    sandPiston(q ? std::vector<int>{100, 200, 400} : std::vector<int>{100, 200, 400, 800}, rep);
  }
  if (wanted("steel-precursor")) {
    say("elastic-plastic wave in steel");
    steelPrecursor(q ? std::vector<int>{200, 400, 800} : std::vector<int>{200, 400, 800, 1600}, rep);
  }
  if (wanted("products-isentrope")) {
    say("CompB slab expanding into air (1D): products against the CJ isentrope");
    productsIsentrope(q ? std::vector<int>{2, 4, 8, 20} : std::vector<int>{2, 4, 8, 20, 80}, rep);
  }
  if (wanted("wet-sand")) {
    say("CompB slab driving 22% wet sand (1D): each material's energy and the sand's momentum against 8x finer cells");
    // 8 cells per slab is short of the asymptotic range (errors of 12-16%), so both levels
    // start at 16
    chargeInWetSand(q ? std::vector<int>{16, 32, 64} : std::vector<int>{16, 32, 64, 128}, rep);
  }
  if (wanted("tnt-free-air")) {
    say("1 kg TNT in free air (1D spherical, the run's settings and early time)");
    tntFreeAir(q ? std::vector<double>{10.0, 5.0, 2.5, 1.25} : std::vector<double>{10.0, 5.0, 2.5, 1.25, 0.625}, rep);
  }
  // Every row that ran the solver has its books checked (each material's mass, and the energy): round-off only.
  for (auto& r : rep.rows) {
    if (!std::isfinite(r.conservation)) continue;
    const bool ok = r.conservation <= kBooksLimit;
    r.passed = (r.check.empty() || r.passed) && ok;
    r.check += fmt::format("{}books <= {:g}", r.check.empty() ? "" : "; ", kBooksLimit);
  }
  return rep;
}

}  // namespace ejecta::verify
