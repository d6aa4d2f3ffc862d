#pragma once
// The verification suite behind `ejecta verify`: the solver against exact solutions, each at
// several resolutions so that the observed order of convergence shows, plus published
// references where no exact solution exists (free-air blast). Kernels only: no files here.
#include <functional>
#include <string>
#include <vector>

namespace ejecta::verify {

struct Row {
  std::string problem;      // e.g. "sod-x"
  std::string geometry;     // e.g. "2D plane", "2D axisymmetric", "3D"
  std::string metric;       // what `error` measures
  int resolution = 0;       // cells along the problem's length scale
  std::size_t cells = 0;    // cells in the mesh
  double error = 0.0;
  double order = 0.0;       // observed order against the previous (coarser) row; NaN for the first
  double conservation = 0.0;// energy books' imbalance (and material mass drift where the box is closed); NaN: not a solver run
  double wall_seconds = 0.0;
  std::string check;        // the acceptance criterion, in words ("" where the row is informative only)
  bool passed = false;      // meaningful only with a check
  long long steps = 0;      // time steps taken
};

struct Profile {
  std::string problem;
  int resolution = 0;
  std::string x_label, y_label;
  std::vector<double> x, numeric, exact;
};

struct Report {
  std::vector<Row> rows;
  std::vector<Profile> profiles;
  bool allPassed() const;
};

struct Options {
  bool quick = true;
  std::vector<std::string> only;                       // problem groups to run (empty: all)
  std::function<void(const std::string&)> log;         // progress messages
};

// How `ejecta run` runs a charge (scenario/case.cpp, scenario/run.cpp), restated for the free-air
// blast row, which sits below the scenario layer; a unit test holds these to the deck's defaults.
struct RunSettings {
  double cfl = 0.30;                            // - the deck's default
  double initial_dt_fraction = 0.1;             // - first step, of the CFL step
  double dt_growth = 1.2;                       // - largest growth of the step from one step to the next
  int charge_paint_samples = 8;                 // sub-samples per axis of a cell cut by the charge
  double air_pressure_pa = 101325.0, air_density_kg_m3 = 1.225;
  double early_cells_per_charge_height = 20.0;  // - the early-time block's resolution
  double early_signal_speed_m_s = 6000.0;       // m/s, the fastest wave the block holds until the map
  double early_reach_burn_times = 4.0;          // the block's reach past the charge: this many burn times at that speed
};

std::vector<std::string> problemGroups();
Report runVerification(const Options& opt);

}  // namespace ejecta::verify
