#pragma once
// Structured meshes for the Eulerian solver: 1D, 1D spherical (r), 2D plane, 2D axisymmetric
// (r, z) and 3D Cartesian from one dimension-generic description. Each axis is a list of face coordinates (a
// uniform core with geometric grading outward is one way to make it); cells carry `kGhost` ghost
// layers on every side so that the same kernels run on a whole domain, an MPI rank's block or a
// GPU tile. SI units: m.
#include <array>
#include <cstddef>
#include <string>
#include <optional>
#include <vector>

namespace ejecta::mesh {

inline constexpr int kGhost = 3;   // the split Lagrange-remap sweep reads 3 cells past a face

// Axisymmetric: axis 0 is r, axis 1 is z, measures per radian. Spherical: 1D, axis 0 is r,
// measures per steradian (a free-air blast resolved at a cost of cells ~ 1/h, not 1/h^2).
enum class Geometry { Cartesian, Axisymmetric, Spherical };

// A rigid free-slip wall and a symmetry plane are the same condition in an inviscid Eulerian
// code: Reflect. (A moving piston is posed in the piston's frame: the material flows in.)
enum class BoundaryKind {
  Reflect,    // symmetry plane, axis or rigid wall: mirror state, normal velocity reversed
  Transmit,   // outflow: zero-gradient extrapolation
  Periodic,
};

// Face coordinates of one axis, interior only (n + 1 faces for n cells).
class Axis {
 public:
  Axis() = default;
  explicit Axis(std::vector<double> faces);   // strictly increasing; throws InputError
  static Axis uniform(double lo, double hi, int cells);
  // A uniform core [core_lo, core_hi] of cell size `dx`, grown by `ratio` per cell outward until
  // the cells reach [lo, hi] (the last cell is stretched or shrunk to land on the end exactly).
  // With an `anchor` inside the core, the core's faces are anchor + k dx exactly (its ends move by
  // under half a cell), so that a plane of the problem (the soil surface) is a face at any dx.
  static Axis graded(double lo, double hi, double core_lo, double core_hi, double dx, double ratio, std::optional<double> anchor = {});

  int cells() const { return static_cast<int>(faces_.size()) - 1; }
  const std::vector<double>& faces() const { return faces_; }
  double lo() const { return faces_.front(); }
  double hi() const { return faces_.back(); }
  double minWidth() const;

 private:
  std::vector<double> faces_;
};

struct Index3 {
  int i = 0, j = 0, k = 0;
};

// The grid of one block: dims in {1, 2, 3}; unused axes have one cell of unit width.
class Grid {
 public:
  Grid(int dims, Geometry geometry, std::array<Axis, 3> axes);

  int dims() const { return dims_; }
  Geometry geometry() const { return geometry_; }
  bool axisymmetric() const { return geometry_ == Geometry::Axisymmetric; }
  bool spherical() const { return geometry_ == Geometry::Spherical; }
  bool curvilinear() const { return geometry_ != Geometry::Cartesian; }   // axis 0 is a radius
  const Axis& axis(int d) const { return axes_[static_cast<std::size_t>(d)]; }
  int cells(int d) const { return n_[static_cast<std::size_t>(d)]; }
  int ghost(int d) const { return d < dims_ ? kGhost : 0; }
  std::size_t interiorCells() const {
    return static_cast<std::size_t>(n_[0]) * static_cast<std::size_t>(n_[1]) * static_cast<std::size_t>(n_[2]);
  }
  std::size_t totalCells() const { return total_; }
  std::ptrdiff_t stride(int d) const { return stride_[static_cast<std::size_t>(d)]; }

  // Flat index of cell (i, j, k); interior cells run 0..n-1, ghosts reach -kGhost..n+kGhost-1.
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>((i + g_[0]) * stride_[0] + (j + g_[1]) * stride_[1] + (k + g_[2]) * stride_[2]);
  }
  Index3 unflatten(std::size_t flat) const;
  bool isInterior(std::size_t flat) const;

  // Per-axis geometry including ghosts: entry [c + ghost] for cell c, faces [f + ghost].
  double face(int d, int f) const { return fx_[static_cast<std::size_t>(d)][static_cast<std::size_t>(f + ghost(d))]; }
  double centre(int d, int c) const { return xc_[static_cast<std::size_t>(d)][static_cast<std::size_t>(c + ghost(d))]; }
  double width(int d, int c) const { return dx_[static_cast<std::size_t>(d)][static_cast<std::size_t>(c + ghost(d))]; }

  double cellVolume(int i, int j, int k) const;   // m3 (axisymmetric: per radian; spherical: per steradian)
  // Face-normal area of the face on the low side of cell (i,j,k) normal to axis d (per radian or steradian).
  double faceArea(int d, int i, int j, int k) const;
  double minWidth() const;
  // Replaces the faces of axis d (the same number of cells, strictly increasing): the mesh of an
  // ALE region that moves with a body. Not the radial axis of an axisymmetric mesh, nor the axis a
  // slab was cut along.
  void moveFaces(int d, Axis moved);

  // The block of cells [begin, end) along axis 0 (one rank's slab of the domain). Its ghost cells
  // along axis 0 keep this grid's geometry (the neighbouring block's cells, or this grid's own
  // ghosts at the domain's ends), so that a kernel reads the same centres and widths in a slab as
  // in the whole. Cell i of the slab is cell i + offset0() of this grid.
  Grid slab(int begin, int end) const;
  int offset0() const { return offset0_; }
  int globalCells0() const { return global0_; }
  bool isSlab() const { return global0_ != n_[0]; }
  // The whole domain's faces along axis 0 (a slab's own axis holds only its part): what a mapping
  // onto a slab needs to treat each of the whole's columns as the whole would.
  const std::vector<double>& wholeFaces0() const { return whole_faces0_.empty() ? axes_[0].faces() : whole_faces0_; }

 private:
  void axisGeometry(int d);   // faces, centres and widths of axis d, ghosts included
  int dims_;
  Geometry geometry_;
  std::array<Axis, 3> axes_;
  std::array<int, 3> n_{1, 1, 1}, g_{0, 0, 0};
  std::array<std::ptrdiff_t, 3> stride_{0, 0, 0};
  std::size_t total_ = 0;
  std::array<std::vector<double>, 3> fx_, xc_, dx_;
  int offset0_ = 0, global0_ = 0;   // a slab's first cell and the whole domain's cells along axis 0
  std::vector<double> whole_faces0_;   // a slab's: the whole's faces along axis 0 (empty in the whole)
};

}  // namespace ejecta::mesh
