#pragma once
// LS-DYNA keyword cards for the sand model: *MAT_PSEUDO_TENSOR (mode I, tabulated yield vs
// pressure) and *EOS_TABULATED_COMPACTION (10 points of ln(V/V0), pressure, unloading modulus).
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "materials/sand_model.hpp"

namespace ejecta::io {

struct LsdynaUnits {
  std::string name;         // "kg-m-s", "g-mm-ms", "t-mm-s"
  double density_factor;    // multiply kg/m3 by this
  double pressure_factor;   // multiply Pa by this
  std::string density_unit, pressure_unit;
};
LsdynaUnits lsdynaUnitsByName(const std::string& name);   // throws InputError("units", ...)

struct CompactionTable {
  std::vector<double> ln_v;        // ln(V/V0): 0, then negative and decreasing
  std::vector<double> pressure;    // Pa
  std::vector<double> unloading;   // Pa
};
// The 10 points that best represent the loading curve up to `p_end` (greedy insertion of the
// point of largest log-pressure interpolation error), the lockup point always included.
CompactionTable chooseCompactionPoints(const materials::SandModel& model, int count = 10);

struct YieldTable {
  std::vector<double> pressure, yield;   // Pa; 16 points
};
YieldTable chooseYieldPoints(const materials::SandModel& model);

struct KeywordOptions {
  LsdynaUnits units;
  int material_id = 1;
  int eos_id = 1;
  std::string description;   // input summary for the header comments
};
void writeLsdynaKeywords(std::ostream& os, const materials::SandModel& model, const KeywordOptions& options);

// Formats a number right-aligned in `width` characters with as many significant digits as fit.
std::string fitField(double v, int width);

// A minimal reader: keyword name -> its data lines (comment lines dropped), in file order.
std::vector<std::pair<std::string, std::vector<std::string>>> readKeywordBlocks(std::istream& is);
// Field `index` of a fixed-width card line (LS-DYNA's fixed format).
double cardField(const std::string& line, int index, int width);

}  // namespace ejecta::io
