// Steps in time: the deck's entries, the integrators (forward Euler, Adams-Bashforth 2), the fixed walls, and the cells' strain rates.
#ifndef dieflow_incremental_time_stepping_h
#define dieflow_incremental_time_stepping_h

#include <dieflow/base/archive.h>
#include <dieflow/mesh/coordinate_system.h>
#include <dieflow/base/parameters.h>
#include <dieflow/mesh/mesh_motion.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <map>
#include <set>
#include <string>
#include <vector>
#include <utility>

namespace dieflow
{
  /**
   * Problem = incremental: the seed paper's "incremental approach" to
   * forming in time. The material is quasi-static, so each step solves the
   * same viscoplastic velocity problem as the steady program on the current
   * configuration x_n; the mesh nodes are material points and move with it.
   * Two integrators of dx/dt = v(x):
   *   forward Euler       x_{n+1} = x_n + dt_n v_n;
   *   Adams-Bashforth 2   x_{n+1} = x_n + dt_n ((1 + r/2) v_n - (r/2) v_{n-1}),
   *                       r = dt_n / dt_{n-1}  (forward Euler on the first step).
   * Both cost one velocity solve per step. Euler's error in the shape is
   * O(dt) over a run, and it does not conserve volume: in homogeneous
   * upsetting each step scales the area by 1 - (V dt / h)^2, half a per
   * cent over a 50 % reduction in 100 steps. Adams-Bashforth 2 takes the
   * previous step's velocity at the same material nodes (free in a
   * Lagrangian mesh) and is second order: the default.
   */
  struct TimeStepping
  {
    enum class Integrator
    {
      adams_bashforth_2,
      forward_euler
    };

    bool         incremental     = false;
    double       time_step       = 0;
    double       end_time        = 0;
    Integrator   integrator      = Integrator::adams_bashforth_2;
    unsigned int output_interval = 1;
    /// Contact entry = within the step (the a priori gap) or after the move.
    bool         contact_within_step = true;

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    /// Steps from t = 0 to End time, the last one shortened to end there.
    unsigned int
    n_steps() const;
    /// t_n (t_0 = 0, t_{n_steps()} = End time).
    double
    time(const unsigned int n) const;
    /// The weights (a, b) of x_{n+1} = x_n + a v_n + b v_{n-1}; forward
    /// Euler's on the first step and where @p restart.
    std::pair<double, double>
    weights(const unsigned int n, const bool restart = false) const;
    /// Whether step @p n writes its fields (every Output interval steps and the last).
    bool
    writes_output(const unsigned int n) const;
  };

  /**
   * The fixed walls of a moving mesh (symmetry planes and lines, the axis,
   * slip walls): the planes of their faces at t = 0, by vertex. A node's
   * velocity normal to a wall is constrained to zero, but at a corner of two
   * walls, or where a wall meets a die, the constraints take mean normals
   * (wall_nodes.h), and the round-off of many steps adds up: keep() puts
   * every node back onto the planes it started on (a node of the axis stays
   * at r = 0, where the axisymmetric weight 2 pi r would turn negative).
   */
  template <int dim>
  class FixedWalls
  {
  public:
    void
    initialize(const dealii::Triangulation<dim> &triangulation, const std::set<BoundaryId> &wall_ids);
    void
    keep(dealii::Triangulation<dim> &triangulation) const;

    /// The planes into a checkpoint, and back.
    void
    save(OutputArchive &ar) const;
    void
    load(InputArchive &ar);

  private:
    /// Per vertex: a point of each wall plane it lies on, and the plane's unit normal.
    std::map<unsigned int, std::vector<std::pair<dealii::Point<dim>, dealii::Tensor<1, dim>>>> planes;
  };

  /**
   * The mean equivalent strain rate sqrt(2/3 D:D) of @p velocity over each
   * active cell (weighted by 2 pi r in the axisymmetric geometry): the rate
   * at which the cell's equivalent strain grows. The strain is carried per
   * cell, and the mesh is Lagrangian, so a cell's strain is its metal's.
   */
  template <int dim>
  dealii::Vector<double>
  cell_strain_rates(const CoordinateSystem<dim> &  coordinates,
                    const dealii::DoFHandler<dim> &dof_handler,
                    const dealii::Vector<double> & velocity);

} // namespace dieflow

#endif
