// The wall constraints at one node, checked by distributing random values:
//  - one inclined wall: v.n = 0 and the tangential component stays free;
//  - a corner of two walls (2D): v = 0;
//  - a wall node whose x component is prescribed (Dirichlet wins on it):
//    v.n = 0 then fixes y through x, whatever x is;
//  - two nearly parallel normals are rejected as dependent (one condition).
#include <dieflow/mesh/wall_nodes.h>

#include <deal.II/lac/vector.h>

#include "report.h"

#include <cmath>
#include <iostream>

using namespace dieflow;

namespace
{
  Tensor<1, 2>
  unit(const double degrees)
  {
    Tensor<1, 2> n;
    n[0] = std::cos(degrees * M_PI / 180);
    n[1] = std::sin(degrees * M_PI / 180);
    return n;
  }

  double
  normal_velocity(const dealii::Vector<double> &v, const Tensor<1, 2> &n)
  {
    return v[0] * n[0] + v[1] * n[1];
  }
} // namespace

int
main()
{
  const std::array<GlobalDof, 2> dofs{{0, 1}};
  {
    AffineConstraints<double> c;
    const auto                n = unit(20 + 90); // die face of a 70-degree die
    constrain_normal_components<2>(dofs, {n}, {0.}, c);
    c.close();
    dealii::Vector<double> v(2);
    v[0] = 0.3, v[1] = -1.7;
    c.distribute(v);
    report("inclined wall: one condition", c.n_constraints() == 1);
    report("inclined wall: v.n = 0", std::abs(normal_velocity(v, n)) < 1e-15);
    report("inclined wall: tangential part free", std::abs(v[0]) + std::abs(v[1]) > 0.1);
  }
  {
    AffineConstraints<double> c;
    constrain_normal_components<2>(dofs, {unit(90), unit(20)}, {0., 0.}, c);
    c.close();
    dealii::Vector<double> v(2);
    v[0] = 0.3, v[1] = -1.7;
    c.distribute(v);
    report("corner: both components held", c.n_constraints() == 2);
    report("corner: v = 0", v.l2_norm() < 1e-15);
  }
  {
    AffineConstraints<double> c;
    c.add_line(0);
    c.set_inhomogeneity(0, 2.0); // prescribed v_x = 2
    const auto n = unit(45);
    constrain_normal_components<2>(dofs, {n}, {0.}, c);
    c.close();
    dealii::Vector<double> v(2);
    c.distribute(v);
    report("prescribed x kept", v[0] == 2.0);
    report("prescribed x: v.n = 0 through y", std::abs(normal_velocity(v, n)) < 1e-14);
  }
  {
    AffineConstraints<double> c;
    constrain_normal_components<2>(dofs, {unit(90), unit(90 + 1e-7)}, {0., 0.}, c);
    c.close();
    report("dependent normals: one condition", c.n_constraints() == 1);
  }
}
