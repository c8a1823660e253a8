// Plane strain or axisymmetric: the measure of every integral (1 or 2 pi r), and the strain rate with its hoop part.
#ifndef dieflow_coordinate_system_h
#define dieflow_coordinate_system_h

#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/vector.h>

#include <cmath>
#include <string>
#include <vector>

namespace dieflow
{
  /// What the 2D mesh stands for (deck entry `Geometry`).
  enum class Geometry
  {
    /// a section of a body of unit depth: forces in N/mm
    plane_strain,
    /// the meridian half-plane of a body of revolution, x the axis, y the radius: forces in N
    axisymmetric
  };

  /// "plane strain" or "axisymmetric", as the deck and summary.json spell it.
  std::string
  geometry_name(const Geometry geometry);

  /**
   * A strain rate with its out-of-plane component: the in-plane part
   * sym grad v and, in the axisymmetric geometry, the hoop rate
   * D_thetatheta = v_r / r (zero in plane strain, where D_zz = 0). The
   * double contraction, the trace (the divergence) and the equivalent rate
   * sqrt(2/3 D:D) are those of the 3x3 tensor
   *   [[D_xx, D_xr, 0], [D_xr, D_rr, 0], [0, 0, v_r/r]],
   * so every constitutive formula of the paper (eqs. (3)-(5)) holds as
   * written for both geometries.
   */
  template <int dim>
  struct StrainRate
  {
    dealii::SymmetricTensor<2, dim> in_plane;
    double                          hoop = 0;

    double
    trace() const
    {
      return dealii::trace(in_plane) + hoop;
    }
    StrainRate &
    operator+=(const StrainRate &other)
    {
      in_plane += other.in_plane;
      hoop += other.hoop;
      return *this;
    }
    StrainRate &
    operator*=(const double factor)
    {
      in_plane *= factor;
      hoop *= factor;
      return *this;
    }
    StrainRate &
    operator/=(const double divisor)
    {
      in_plane /= divisor;
      hoop /= divisor;
      return *this;
    }
  };

  /// D:E, the hoop parts included.
  template <int dim>
  inline double
  operator*(const StrainRate<dim> &D, const StrainRate<dim> &E)
  {
    return D.in_plane * E.in_plane + D.hoop * E.hoop;
  }

  template <int dim>
  inline StrainRate<dim>
  operator*(const double factor, StrainRate<dim> D)
  {
    return D *= factor;
  }

  template <int dim>
  inline StrainRate<dim>
  operator*(StrainRate<dim> D, const double factor)
  {
    return D *= factor;
  }

  template <int dim>
  inline StrainRate<dim>
  operator/(StrainRate<dim> D, const double divisor)
  {
    return D /= divisor;
  }

  template <int dim>
  inline StrainRate<dim>
  operator+(StrainRate<dim> D, const StrainRate<dim> &E)
  {
    return D += E;
  }

  template <int dim>
  inline StrainRate<dim>
  operator-(StrainRate<dim> D, const StrainRate<dim> &E)
  {
    return D += -1. * E;
  }

  /**
   * The hoop rate v_r / r at a point of the meridian plane where values
   * are sampled rather than integrated (output points, vertices): on the
   * axis, where v_r = 0, its limit dv_r/dr.
   */
  template <int dim>
  inline double
  hoop_rate(const dealii::Point<dim> &x, const double radial_velocity, const double radial_derivative)
  {
    return std::abs(x[1]) > 1e-10 ? radial_velocity / x[1] : radial_derivative;
  }

  /**
   * The measure and the kinematics of the geometry, for every integral of
   * the weak form (the paper's (7)-(9) and the contact element's nodal
   * weights): in plane strain dV = dx dy and dA = ds (per mm of depth); in
   * the axisymmetric geometry the body of revolution about the x axis,
   * dV = 2 pi r dx dr and dA = 2 pi r ds with r = y, so that every force
   * (reactions, die forces, the ram force) is the whole body's, in N, and
   * the strain rate gains the hoop rate v_r / r, the divergence
   * div v = dv_x/dx + dv_r/dr + v_r/r.
   *
   * The hoop rate is evaluated at quadrature points, which are interior to
   * the cells, so r > 0 there; on the axis v_r = 0 is imposed (a symmetry
   * line), which keeps v_r / r bounded.
   */
  template <int dim>
  class CoordinateSystem
  {
  public:
    explicit CoordinateSystem(const Geometry geometry = Geometry::plane_strain)
      : geometry(geometry)
    {}

    Geometry
    kind() const
    {
      return geometry;
    }

    bool
    axisymmetric() const
    {
      return geometry == Geometry::axisymmetric;
    }

    /**
     * True where the Q1 element's one-point (cell centre) rule gives the
     * exact cell mean of div v, int_K div v dx = div v(c) |K|: plane strain,
     * where div v det J is bilinear on the reference square. Not in 3D,
     * where det J times the divergence of a trilinear field is quadratic in
     * each reference coordinate on a cell that is not a parallelepiped (a
     * constant pressure would then not be in equilibrium with its boundary
     * tractions: an O(1) error on distorted meshes, whatever the penalty),
     * nor in the axisymmetric geometry (the 2 pi r weight): there the
     * degree-1 penalty acts on the cell mean from the 2^dim Gauss rule
     * (mean dilatation, PressureProjection).
     */
    bool
    centre_rule_is_mean() const
    {
      return dim == 2 && !axisymmetric();
    }

    /// The factor of dx dy (and of ds) at @p x: 1, or 2 pi r.
    double
    weight(const dealii::Point<dim> &x) const
    {
      return axisymmetric() ? 2. * dealii::numbers::PI * x[1] : 1.;
    }

    /// The update flags an FEValues needs on top of its own for strain_rate() and divergence().
    dealii::UpdateFlags
    flags() const
    {
      return axisymmetric() ? dealii::update_values | dealii::update_quadrature_points : dealii::update_default;
    }

    /// D(phi_i) at quadrature point q (the FEValues of a vector element whose velocity starts at component 0).
    StrainRate<dim>
    strain_rate(const dealii::FEValuesBase<dim> &fe_values, const unsigned int i, const unsigned int q) const
    {
      StrainRate<dim> D;
      D.in_plane = fe_values[velocities].symmetric_gradient(i, q);
      if (axisymmetric())
        D.hoop = fe_values[velocities].value(i, q)[1] / fe_values.quadrature_point(q)[1];
      return D;
    }

    /// div phi_i at quadrature point q, the hoop rate included.
    double
    divergence(const dealii::FEValuesBase<dim> &fe_values, const unsigned int i, const unsigned int q) const
    {
      double div = fe_values[velocities].divergence(i, q);
      if (axisymmetric())
        div += fe_values[velocities].value(i, q)[1] / fe_values.quadrature_point(q)[1];
      return div;
    }

    /// Whether @p face lies on the axis y = 0 (axisymmetric only): a line of zero area.
    template <typename FaceIterator>
    bool
    on_axis(const FaceIterator &face) const
    {
      if (!axisymmetric())
        return false;
      for (const unsigned int v : face->vertex_indices())
        if (std::abs(face->vertex(v)[1]) > 1e-10 * face->diameter())
          return false;
      return true;
    }

    /// D(v) at every quadrature point of @p fe_values, for a global dof vector @p v.
    void
    strain_rates(const dealii::FEValuesBase<dim> &   fe_values,
                 const dealii::Vector<double> &      v,
                 std::vector<StrainRate<dim>> &      D) const;

  private:
    Geometry                           geometry;
    dealii::FEValuesExtractors::Vector velocities{0};
  };
} // namespace dieflow

#endif
