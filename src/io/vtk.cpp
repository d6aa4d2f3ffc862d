#include "io/vtk.hpp"

#include <fmt/format.h>

#include "io/report.hpp"   // escapeHtml: the same escaping an XML attribute needs

namespace ejecta::io {

namespace {

// The arrays a snapshot holds, in file order: a piece and its index (.pvtr) name them alike.
struct ArrayInfo {
  std::string name, type;
  int components = 1;
};
std::vector<ArrayInfo> cellArrays(const hydro::Solver& s) {
  std::vector<ArrayInfo> a;
  for (const auto& m : s.materials()) a.push_back({escapeHtml("alpha_" + m.name), "Float64"});
  a.push_back({"density", "Float64"});
  a.push_back({"pressure", "Float64"});
  a.push_back({"velocity", "Float64", 3});
  a.push_back({"target", "UInt8"});
  return a;
}
// type, name and components, as a DataArray (a piece) and a PDataArray (the index) both declare them
std::string attributes(const ArrayInfo& a) {
  return fmt::format("type=\"{}\" Name=\"{}\"{}", a.type, a.name, a.components > 1 ? fmt::format(" NumberOfComponents=\"{}\"", a.components) : std::string());
}
const char* axisName(const mesh::Grid& g, int d) { return d == 0 ? (g.axisymmetric() ? "r" : "x") : (d == 1 ? (g.axisymmetric() ? "z" : "y") : "z3"); }

}  // namespace

void writeVtr(std::ostream& os, const hydro::Solver& s) {
  const auto& g = s.grid();
  // a slab's cells sit at its offset along axis 0 in the whole's numbering
  const int i0 = g.offset0(), n0 = g.cells(0), n1 = g.cells(1), n2 = g.dims() == 3 ? g.cells(2) : 0;
  // A piece's WholeExtent is its own extent, as VTK's parallel writers give their pieces: each opens alone.
  const std::string extent = fmt::format("{} {} 0 {} 0 {}", i0, i0 + n0, n1, n2);
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"RectilinearGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  os << fmt::format("<RectilinearGrid WholeExtent=\"{}\">\n<Piece Extent=\"{}\">\n", extent, extent);
  os << "<Coordinates>\n";
  for (int d = 0; d < 3; ++d) {
    os << fmt::format("<DataArray type=\"Float64\" Name=\"{}\" format=\"ascii\">\n", axisName(g, d));
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
  const auto arrays = cellArrays(s);
  auto open = [&](const ArrayInfo& a) {
    os << fmt::format("<DataArray {} format=\"ascii\">\n", attributes(a));
  };
  std::size_t next = 0;
  for (int m = 0; m < s.materialCount(); ++m) {
    open(arrays[next++]);
    cells([&](std::size_t c) { os << fmt::format("{:.6g} ", s.isBody(c) ? 0.0 : s.field(m).alpha[c]); });
    os << "\n</DataArray>\n";
  }
  open(arrays[next++]);
  cells([&](std::size_t c) { os << fmt::format("{:.6g} ", s.isBody(c) ? 0.0 : s.density(c)); });
  os << "\n</DataArray>\n";
  open(arrays[next++]);
  cells([&](std::size_t c) { os << fmt::format("{:.6g} ", s.isBody(c) ? 0.0 : s.pressure(c)); });
  os << "\n</DataArray>\n";
  open(arrays[next++]);
  cells([&](std::size_t c) { os << fmt::format("{:.6g} {:.6g} {:.6g} ", s.velocity(0)[c], s.velocity(1)[c], s.velocity(2)[c]); });
  os << "\n</DataArray>\n";
  open(arrays[next++]);
  cells([&](std::size_t c) { os << (s.isBody(c) ? "1 " : "0 "); });
  os << "\n</DataArray>\n</CellData>\n</Piece>\n</RectilinearGrid>\n</VTKFile>\n";
}

void writePvtr(std::ostream& os, const hydro::Solver& slab, const std::vector<VtrPiece>& pieces) {
  const auto& g = slab.grid();
  const int n1 = g.cells(1), n2 = g.dims() == 3 ? g.cells(2) : 0;
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PRectilinearGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  os << fmt::format("<PRectilinearGrid WholeExtent=\"0 {} 0 {} 0 {}\" GhostLevel=\"0\">\n", g.globalCells0(), n1, n2);
  os << "<PCoordinates>\n";
  for (int d = 0; d < 3; ++d) os << fmt::format("<PDataArray type=\"Float64\" Name=\"{}\"/>\n", axisName(g, d));
  os << "</PCoordinates>\n<PCellData Scalars=\"density\" Vectors=\"velocity\">\n";
  for (const auto& a : cellArrays(slab))
    os << fmt::format("<PDataArray {}/>\n", attributes(a));
  os << "</PCellData>\n";
  for (const auto& p : pieces) os << fmt::format("<Piece Extent=\"{} {} 0 {} 0 {}\" Source=\"{}\"/>\n", p.begin, p.end, n1, n2, p.file);
  os << "</PRectilinearGrid>\n</VTKFile>\n";
}

void writePvd(std::ostream& os, const std::vector<std::pair<double, std::string>>& snapshots) {
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  for (const auto& [t, file] : snapshots) os << fmt::format("<DataSet timestep=\"{:.9g}\" file=\"{}\"/>\n", t, file);
  os << "</Collection>\n</VTKFile>\n";
}

}  // namespace ejecta::io
