#include "io/vtk.hpp"

#include <fmt/format.h>

namespace ejecta::io {

void writeVtr(std::ostream& os, const hydro::Solver& s) {
  const auto& g = s.grid();
  const int n0 = g.cells(0), n1 = g.cells(1), n2 = g.dims() == 3 ? g.cells(2) : 0;
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"RectilinearGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  os << fmt::format("<RectilinearGrid WholeExtent=\"0 {} 0 {} 0 {}\">\n<Piece Extent=\"0 {} 0 {} 0 {}\">\n", n0, n1, n2, n0, n1, n2);
  os << "<Coordinates>\n";
  for (int d = 0; d < 3; ++d) {
    os << fmt::format("<DataArray type=\"Float64\" Name=\"{}\" format=\"ascii\">\n", d == 0 ? (g.axisymmetric() ? "r" : "x") : (d == 1 ? (g.axisymmetric() ? "z" : "y") : "z3"));
    if (d < g.dims())
      for (const double f : g.axis(d).faces()) os << fmt::format("{:.9g} ", f);
    else
      os << "0";
    os << "\n</DataArray>\n";
  }
  os << "</Coordinates>\n<CellData Scalars=\"density\" Vectors=\"velocity\">\n";
  auto cells = [&](auto&& value) {
    // VTK orders cells with x fastest
    for (int k = 0; k < g.cells(2); ++k)
      for (int j = 0; j < n1; ++j)
        for (int i = 0; i < n0; ++i) value(g.index(i, j, k));
  };
  for (int m = 0; m < s.materialCount(); ++m) {
    os << fmt::format("<DataArray type=\"Float64\" Name=\"alpha_{}\" format=\"ascii\">\n", s.materials()[static_cast<std::size_t>(m)].name);
    cells([&](std::size_t c) { os << fmt::format("{:.6g} ", s.isBody(c) ? 0.0 : s.field(m).alpha[c]); });
    os << "\n</DataArray>\n";
  }
  os << "<DataArray type=\"Float64\" Name=\"density\" format=\"ascii\">\n";
  cells([&](std::size_t c) { os << fmt::format("{:.6g} ", s.isBody(c) ? 0.0 : s.density(c)); });
  os << "\n</DataArray>\n<DataArray type=\"Float64\" Name=\"pressure\" format=\"ascii\">\n";
  cells([&](std::size_t c) { os << fmt::format("{:.6g} ", s.isBody(c) ? 0.0 : s.pressure(c)); });
  os << "\n</DataArray>\n<DataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  cells([&](std::size_t c) { os << fmt::format("{:.6g} {:.6g} {:.6g} ", s.velocity(0)[c], s.velocity(1)[c], s.velocity(2)[c]); });
  os << "\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"target\" format=\"ascii\">\n";
  cells([&](std::size_t c) { os << (s.isBody(c) ? "1 " : "0 "); });
  os << "\n</DataArray>\n</CellData>\n</Piece>\n</RectilinearGrid>\n</VTKFile>\n";
}

void writePvd(std::ostream& os, const std::vector<std::pair<double, std::string>>& snapshots) {
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  for (const auto& [t, file] : snapshots) os << fmt::format("<DataSet timestep=\"{:.9g}\" file=\"{}\"/>\n", t, file);
  os << "</Collection>\n</VTKFile>\n";
}

}  // namespace ejecta::io
