// Steps in time: the deck's entries, the integrators (forward Euler, Adams-Bashforth 2), the fixed walls, and the cells' strain rates.
#include <dieflow/base/serialization.h>
#include <dieflow/incremental/time_stepping.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace dieflow
{
  void
  TimeStepping::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Problem",
                      "steady",
                      dealii::Patterns::Selection("steady|incremental"),
                      "steady: the flow through fixed dies on a fixed domain, with "
                      "refinement cycles (subsection Refinement). incremental: forming "
                      "in time (upsetting, forging, the start of an extrusion): every "
                      "step solves the velocity on the current configuration and the "
                      "mesh moves with the metal (subsection Incremental); the forces "
                      "of every step go to load-stroke.txt.");
    prm.enter_subsection("Incremental");
    prm.declare_entry("Time step",
                      "0.01",
                      dealii::Patterns::Double(0),
                      "dt in s. The step's stroke, dt times the ram speed, should stay "
                      "below about a hundredth of the height of the work piece (the "
                      "shape's error grows as dt^2 with Adams-Bashforth 2, as dt with "
                      "forward Euler; doc/incremental.md).");
    prm.declare_entry("End time", "0.1", dealii::Patterns::Double(0), "The time the run ends at, in s.");
    prm.declare_entry("Integrator",
                      "Adams-Bashforth 2",
                      dealii::Patterns::Selection("Adams-Bashforth 2|forward Euler"),
                      "How the nodes move: Adams-Bashforth 2, x += dt (3/2 v_n - 1/2 "
                      "v_{n-1}) (second order, one solve per step; Euler on the first "
                      "step), or forward Euler, x += dt v_n (first order; it loses volume "
                      "as dt).");
    prm.declare_entry("Output interval",
                      "1",
                      dealii::Patterns::Integer(1),
                      "Write the fields (Write VTU, Write gnuplot) of every this many "
                      "steps, and of the last; solution.pvd indexes them by time.");
    prm.declare_entry("Contact entry",
                      "within the step",
                      dealii::Patterns::Selection("within the step|after the move"),
                      "How a node of the free surface comes onto a die. within the step: "
                      "the paper's gap g_n + dt (v_s - v_die).n <= 0 in the step's solve "
                      "(nodes over a die within reach of it are held to (v - V).n <= g/dt, "
                      "so that one that would go through it lands on it; the move is then "
                      "forward Euler's). after the move: the node goes through and is put "
                      "back onto the die, the volume it went through lost (as before; "
                      "doc/incremental.md compares the two).");
    prm.leave_subsection();
  }



  void
  TimeStepping::parse_parameters(ParameterHandler &prm)
  {
    incremental = prm.get("Problem") == "incremental";
    prm.enter_subsection("Incremental");
    time_step       = prm.get_double("Time step");
    end_time        = prm.get_double("End time");
    integrator      = prm.get("Integrator") == "forward Euler" ? Integrator::forward_euler :
                                                                  Integrator::adams_bashforth_2;
    output_interval = prm.get_integer("Output interval");
    contact_within_step = prm.get("Contact entry") == "within the step";
    prm.leave_subsection();
    if (!incremental)
      return;
    require(time_step > 0, "Incremental/Time step", "must be positive");
    require(end_time > 0, "Incremental/End time", "must be positive");
    require(end_time / time_step <= 1e6,
            "Incremental/Time step",
            "End time / Time step = " + deck_number(end_time / time_step) + " steps; at most a million");
  }



  unsigned int
  TimeStepping::n_steps() const
  {
    // A last step shorter than 1e-9 dt is round-off of End time / dt.
    return std::max(1u, static_cast<unsigned int>(std::ceil(end_time / time_step - 1e-9)));
  }



  double
  TimeStepping::time(const unsigned int n) const
  {
    return n >= n_steps() ? end_time : n * time_step;
  }



  std::pair<double, double>
  TimeStepping::weights(const unsigned int n, const bool restart) const
  {
    const double dt = time(n + 1) - time(n);
    if (integrator == Integrator::forward_euler || n == 0 || restart)
      return {dt, 0.};
    const double r = dt / (time(n) - time(n - 1));
    return {dt * (1. + 0.5 * r), -dt * 0.5 * r};
  }



  bool
  TimeStepping::writes_output(const unsigned int n) const
  {
    return n % output_interval == 0 || n == n_steps();
  }



  template <int dim>
  void
  FixedWalls<dim>::initialize(const dealii::Triangulation<dim> &triangulation, const std::set<BoundaryId> &wall_ids)
  {
    // The planes known (at t = 0: none; after a new mesh: the walls' as they
    // were at t = 0). A new mesh's wall faces lie on them to round-off: they
    // take the known plane, not their own. Planes taken from the faces each
    // time would tilt by the round-off of the nodes' positions, the nodes
    // then moving along the tilted planes went off them further, and the
    // next new mesh took that: with a new mesh every few steps the error
    // grows from round-off until a kinked axis holds the metal back
    // (doc/benchmarks.md, "Figures behind the code's rules").
    std::vector<std::pair<dealii::Point<dim>, dealii::Tensor<1, dim>>> known;
    for (const auto &[vertex, list] : planes)
      for (const auto &plane : list)
        if (std::none_of(known.begin(), known.end(), [&](const auto &k) {
              return std::abs(std::abs(k.second * plane.second) - 1) < 1e-12 &&
                     std::abs((plane.first - k.first) * k.second) <= 1e-12 * (1 + plane.first.norm());
            }))
          known.push_back(plane);
    planes.clear();
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary() && wall_ids.count(cell->face(f)->boundary_id()))
          {
            const auto face = cell->face(f);
            // The walls are flat: the normal at the face's centre is the plane's.
            dealii::Tensor<1, dim> normal;
            if constexpr (dim == 2)
              {
                const auto t = face->vertex(1) - face->vertex(0);
                normal       = dealii::Tensor<1, dim>({t[1], -t[0]});
              }
            else
              normal = dealii::cross_product_3d(face->vertex(3) - face->vertex(0), face->vertex(2) - face->vertex(1));
            normal /= normal.norm();
            const double tolerance = 1e-6 * face->diameter();
            const auto   on_it     = [&](const std::pair<dealii::Point<dim>, dealii::Tensor<1, dim>> &k) {
              if (std::abs(std::abs(k.second * normal) - 1) >= 1e-6)
                return false;
              for (const unsigned int v : face->vertex_indices())
                if (std::abs((face->vertex(v) - k.first) * k.second) > tolerance)
                  return false;
              return true;
            };
            const auto wall = std::find_if(known.begin(), known.end(), on_it);
            for (const unsigned int v : face->vertex_indices())
              {
                // A face on no known wall: the plane through each of its vertices.
                const auto plane = wall != known.end() ? *wall : std::make_pair(face->vertex(v), normal);
                auto &     list  = planes[face->vertex_index(v)];
                bool       known_here = false;
                for (const auto &[point, n] : list)
                  known_here = known_here || std::abs(std::abs(n * plane.second) - 1) < 1e-12;
                if (!known_here)
                  list.push_back(plane);
              }
          }
  }



  template <int dim>
  void
  FixedWalls<dim>::keep(dealii::Triangulation<dim> &triangulation) const
  {
    std::vector<bool> done(triangulation.n_vertices(), false);
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        {
          const unsigned int index = cell->vertex_index(v);
          const auto         walls = planes.find(index);
          if (done[index] || walls == planes.end())
            continue;
          done[index] = true;
          for (const auto &[point, normal] : walls->second)
            cell->vertex(v) -= ((cell->vertex(v) - point) * normal) * normal;
        }
  }



  template <int dim>
  void
  FixedWalls<dim>::save(OutputArchive &ar) const
  {
    ar << planes;
  }



  template <int dim>
  void
  FixedWalls<dim>::load(InputArchive &ar)
  {
    ar >> planes;
  }



  template <int dim>
  dealii::Vector<double>
  cell_strain_rates(const CoordinateSystem<dim> &  coordinates,
                    const dealii::DoFHandler<dim> &dof_handler,
                    const dealii::Vector<double> & velocity)
  {
    const auto &              fe = dof_handler.get_fe();
    const dealii::QGauss<dim> quadrature(fe.degree + 1);
    dealii::FEValues<dim>     fe_values(fe,
                                    quadrature,
                                    dealii::update_gradients | dealii::update_JxW_values |
                                      dealii::update_quadrature_points | coordinates.flags());
    std::vector<dealii::types::global_dof_index> dofs(fe.n_dofs_per_cell());
    dealii::Vector<double>                       rates(dof_handler.get_triangulation().n_active_cells());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        cell->get_dof_indices(dofs);
        double integral = 0, volume = 0;
        for (const unsigned int q : fe_values.quadrature_point_indices())
          {
            StrainRate<dim> D;
            for (unsigned int i = 0; i < dofs.size(); ++i)
              D += velocity[dofs[i]] * coordinates.strain_rate(fe_values, i, q);
            const double JxW = fe_values.JxW(q) * coordinates.weight(fe_values.quadrature_point(q));
            integral += std::sqrt(2. / 3. * (D * D)) * JxW;
            volume += JxW;
          }
        rates[cell->active_cell_index()] = integral / volume;
      }
    return rates;
  }



  template class FixedWalls<2>;
  template class FixedWalls<3>;
  template dealii::Vector<double>
  cell_strain_rates(const CoordinateSystem<2> &, const dealii::DoFHandler<2> &, const dealii::Vector<double> &);
  template dealii::Vector<double>
  cell_strain_rates(const CoordinateSystem<3> &, const dealii::DoFHandler<3> &, const dealii::Vector<double> &);
} // namespace dieflow
