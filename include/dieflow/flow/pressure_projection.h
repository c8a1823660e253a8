// The penalty's discontinuous pressure space per cell, the projection P of div v onto it, and the divergence and pressure per cell.
#ifndef dieflow_pressure_projection_h
#define dieflow_pressure_projection_h

#include <dieflow/mesh/coordinate_system.h>

#include <deal.II/base/point.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <vector>

namespace dieflow
{
  using dealii::DoFHandler;
  using dealii::Tensor;
  using dealii::Vector;

  /**
   * The discontinuous pressure space of the penalty term, per cell K, and
   * the L2 projection P of div v onto it: the penalty reads
   *   int lambda (P div v)(P div w) dx = lambda (B_K v)^T M_K^-1 (B_K w),
   *   B_K[m][i] = int_K psi_m div phi_i dx,  M_K[m][n] = int_K psi_m psi_n dx,
   * and the pressure is p = -lambda P div v (paper, eq. (8)).
   *
   * Velocity degree 1 (the paper's Q1-P0): psi_0 = 1 and one quadrature
   * point at the cell centre, so P div v = div v(centre), the selective
   * reduced integration of the seed paper.
   *
   * Velocity degree 2 (the inf-sup stable Q2-P1disc pair): psi = 1,
   * (x - x_K)/h_K, (y - y_K)/h_K [, (z - z_K)/h_K] in real coordinates,
   * x_K the centroid and h_K = |K|^(1/dim), integrated with 3x3 Gauss
   * points (exact for the trapezoids of straight-sided meshes). A P1 basis
   * mapped from the reference cell would lose an order of accuracy on cells
   * that are not parallelograms (Arnold, Boffi, Falk, Math. Comp. 71
   * (2002) 909), and die2d's cells are trapezoids. With psi_1.. of zero
   * mean, the first coefficient is the cell mean.
   *
   * Axisymmetric geometry (CoordinateSystem): dx becomes 2 pi r dx dr in
   * B_K and M_K and div v gains v_r / r, so P is the L2 projection in the
   * weighted space and lambda B^T M^-1 B the penalty of the body of
   * revolution; the basis, its centroid and h_K stay those of the section.
   * For degree 1, P div v is then the weighted cell mean of div v (2x2
   * Gauss points: the mean dilatation of Nagtegaal, Parks and Rice, Comput.
   * Methods Appl. Mech. Eng. 4 (1974) 153), not its centre value: the
   * weight 2 pi r and the hoop term v_r/r vary across the cell, and a
   * centre-point constraint then lets each cell gain or lose volume
   * (doc/benchmarks.md, "Figures behind the code's rules").
   */
  template <int dim>
  class PressureProjection
  {
  public:
    explicit PressureProjection(const dealii::FiniteElement<dim> &fe,
                                const CoordinateSystem<dim> &     coordinates = CoordinateSystem<dim>());

    PressureProjection(const PressureProjection &other)
      : PressureProjection(other.fe_values.get_fe(), other.coordinates)
    {}

    /// Coefficients per cell: 1 (degree 1), dim + 1 (degree 2), or the
    /// (dim + 1)(dim + 2)/2 of P2 (degree 3: Q3-P2disc, the richer space
    /// in which the goal-oriented estimate solves its dual problem).
    unsigned int
    n_modes() const
    {
      return modes;
    }

    /// The same, for a velocity element.
    static unsigned int
    n_modes_for(const dealii::FiniteElement<dim> &fe)
    {
      return fe.degree == 1 ? 1 : fe.degree == 2 ? dim + 1 : (dim + 1) * (dim + 2) / 2;
    }

    /// B_K, M_K^-1, the centroid and h_K of @p cell.
    void
    reinit(const typename dealii::DoFHandler<dim>::active_cell_iterator &cell);

    /// B_K (n_modes x dofs per cell), for the last reinit().
    const dealii::FullMatrix<double> &
    divergence_matrix() const
    {
      return B;
    }

    /// M_K, for the last reinit().
    const dealii::FullMatrix<double> &
    mass() const
    {
      return M;
    }

    /// h_K = |K|^(1/dim), for the last reinit().
    double
    cell_size() const
    {
      return h;
    }

    /// M_K^-1, for the last reinit().
    const dealii::FullMatrix<double> &
    inverse_mass() const
    {
      return M_inverse;
    }

    /// The coefficients of P div v on the cell from its local dof values.
    void
    project(const std::vector<double> &local_velocity, dealii::Vector<double> &coefficients) const;

    /// reinit() on @p cell, then the coefficients of P div v there from the
    /// global dof vector @p velocity.
    void
    project(const typename dealii::DoFHandler<dim>::active_cell_iterator &cell,
            const dealii::Vector<double> &                                velocity,
            dealii::Vector<double> &                                      coefficients);

    /// The value at @p x of the field with the given coefficients on the cell.
    double
    value(const double *coefficients, const dealii::Point<dim> &x) const;

    /// The integral of the square of that field over the cell.
    double
    square_integral(const double *coefficients) const;

    /// The coefficients of P div v on every active cell, cell after cell.
    static dealii::Vector<double>
    project_all(const dealii::DoFHandler<dim> &dof_handler,
                const dealii::Vector<double> & velocity,
                const CoordinateSystem<dim> &  coordinates);

  private:
    static constexpr unsigned int max_modes = (dim + 1) * (dim + 2) / 2;
    /// The basis functions at @p x (n_modes() values).
    void
    basis(const dealii::Point<dim> &x, double *psi) const;

    unsigned int               modes;
    CoordinateSystem<dim>      coordinates;
    dealii::FEValues<dim>      fe_values;
    dealii::FullMatrix<double> B;
    dealii::FullMatrix<double> M_inverse;
    dealii::FullMatrix<double> M;
    dealii::Point<dim>         centroid;
    double                     h = 1;
    std::vector<dealii::types::global_dof_index> cell_dofs;
    std::vector<double>                          cell_velocity;
  };

  /**
   * ||P div v|| / ||grad v|| in L2, P the projection of the penalty term
   * (PressureProjection): what the penalty controls. Degree 1: div v at the
   * cell centres (the cell mean of div v on parallelograms, the discrete
   * mass balance of the Q1-P0 pair); degree 2: the P1disc projection.
   */
  template <int dim>
  double
  divergence_ratio(const CoordinateSystem<dim> &coordinates, const DoFHandler<dim> &dof_handler, const Vector<double> &velocity);

  /// The coefficients of P div v per cell (PressureProjection::n_modes()
  /// each): degree 1 div v at the cell centre (what the one-point penalty
  /// term sees), degree 2 the P1disc projection.
  template <int dim>
  Vector<double>
  cell_divergence(const CoordinateSystem<dim> &coordinates, const DoFHandler<dim> &dof_handler, const Vector<double> &velocity);

  /// Pressure p = -(q + lambda P div v), its coefficients per cell as
  /// cell_divergence() (q: the augmented-Lagrangian multiplier, if any;
  /// lambda per cell if given).
  template <int dim>
  Vector<double>
  cell_pressure(const CoordinateSystem<dim> &coordinates,
                const DoFHandler<dim> &dof_handler,
                const Vector<double> & velocity,
                const double           penalty,
                const Vector<double> * multiplier,
                const Vector<double> * cell_penalty);
} // namespace dieflow

#endif
