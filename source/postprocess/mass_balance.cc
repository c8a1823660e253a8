// How much mass the penalty lets the metal lose: the two measures, the guard's verdict on them, and what to change when it fails.
#include <dieflow/postprocess/mass_balance.h>
#include <dieflow/flow/material.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include <cmath>
#include <iomanip>
#include <sstream>

namespace dieflow
{
  template <int dim>
  MassBalance
  mass_balance(const CoordinateSystem<dim> &       coordinates,
               const DoFHandler<dim> &             dof_handler,
               const Vector<double> &              velocity,
               const std::map<BoundaryId, double> &flux)
  {
    double inflow = 0, outflow = 0, net = 0;
    for (const auto &[id, q] : flux)
      {
        net += q;
        (q < 0 ? inflow : outflow) += std::abs(q);
      }
    MassBalance balance;
    balance.reference_flux = std::max(inflow, outflow);
    if (balance.reference_flux == 0)
      return balance;

    // The cell integral of div v is what each cell gains or loses; Gauss
    // points of degree + 1 integrate it exactly on parallelograms.
    const auto &                             fe = dof_handler.get_fe();
    dealii::FEValues<dim>                    values(fe, dealii::QGauss<dim>(fe.degree + 1),
                                 dealii::update_gradients | dealii::update_JxW_values | dealii::update_quadrature_points |
                                   coordinates.flags());
    std::vector<StrainRate<dim>>             D(values.n_quadrature_points);
    double                                   volume_change = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        values.reinit(cell);
        coordinates.strain_rates(values, velocity, D);
        double change = 0;
        for (const unsigned int q : values.quadrature_point_indices())
          change += D[q].trace() * values.JxW(q) * coordinates.weight(values.quadrature_point(q));
        volume_change += std::abs(change);
      }
    balance.loss          = std::abs(net) / balance.reference_flux;
    balance.volume_change = volume_change / balance.reference_flux;
    return balance;
  }



  std::string
  status_name(const MassBalanceStatus status)
  {
    switch (status)
      {
        case MassBalanceStatus::off:
          return "off";
        case MassBalanceStatus::ok:
          return "ok";
        case MassBalanceStatus::warning:
          return "warning";
        case MassBalanceStatus::failed:
          return "failed";
        default:
          return "";
      }
  }



  MassBalanceStatus
  mass_balance_status(const MassBalance &balance, const double tolerance)
  {
    if (balance.worst() > tolerance)
      return MassBalanceStatus::failed;
    return balance.worst() > 0.1 * tolerance ? MassBalanceStatus::warning : MassBalanceStatus::ok;
  }



  std::string
  mass_balance_advice(const MassBalance &balance,
                      const double       tolerance,
                      const double       penalty_factor,
                      const MassHold     hold,
                      const double       divergence_tolerance)
  {
    std::ostringstream advice;
    if (hold == MassHold::uzawa_stalled)
      return "Uzawa steps no longer reduce div v: no incompressible flow on this mesh meets the boundary "
             "conditions (the elements lock); refine the mesh (more cells across) or set Discretisation/Velocity "
             "degree = 2";
    if (hold == MassHold::uzawa)
      {
        advice << "lower Linear solver/Divergence tolerance (it is " << deck_number(divergence_tolerance) << ")";
        return advice.str();
      }
    // The penalty's compressibility scales as 1/lambda: the factor that
    // brings the worse measure to a hundredth of the tolerance, rounded
    // up to a power of ten.
    constexpr double largest = Material::largest_penalty_factor;
    const double     needed =
      std::pow(10., std::ceil(std::log10(penalty_factor * balance.worst() / (0.01 * tolerance)) - 1e-9));
    if (penalty_factor >= largest)
      advice << "Material/Penalty factor = " << deck_number(penalty_factor)
             << " is already at the limit of double precision (round-off grows as the factor); use Linear "
                "solver/Method = iterative, whose augmented Lagrangian drives div v below its Divergence tolerance";
    else
      advice << "raise Material/Penalty factor (it is " << deck_number(penalty_factor) << ") to "
             << deck_number(std::min(needed, largest))
             << (needed > largest ? ", the limit of double precision" : "");
    return advice.str();
  }



  template MassBalance
  mass_balance<2>(const CoordinateSystem<2> &, const DoFHandler<2> &, const Vector<double> &, const std::map<BoundaryId, double> &);
  template MassBalance
  mass_balance<3>(const CoordinateSystem<3> &, const DoFHandler<3> &, const Vector<double> &, const std::map<BoundaryId, double> &);
} // namespace dieflow
