// The contact element (slave node + master segment, moving master) against
// finite differences: its residual's derivative in the six velocities
// u = (v_s, v_1, v_2) must be its tangent, for every friction law and state,
// with the normal force either given (active set: also dR/dF_n) or from the
// penalty (then the non-symmetric SL terms). Central differences with step
// 1e-6 |u| have a truncation error of 1e-12 relative (the element is
// piecewise quadratic in u): tolerance 1e-7. Also: c_n, c_t are the
// variations of the gap rates, slip sits on the Coulomb cone, stick below it.
#include <dieflow/contact/contact_element.h>

#include "report.h"

#include <cmath>

using namespace dieflow;
using Element = ContactElement<2>;

namespace
{
  Element::Vector
  velocities(const double shift)
  {
    Element::Vector u;
    for (int i = 0; i < Element::size; ++i)
      u[i] = std::sin(1.7 * i + shift) * (i < 2 ? 3. : 0.5);
    return u;
  }

  // Largest relative gap between the tangent and central differences.
  template <typename Residual>
  double
  tangent_error(const Residual &residual, const Element::Matrix &tangent, const Element::Vector &u)
  {
    const double    e = 1e-6 * u.norm();
    Element::Matrix fd;
    for (int j = 0; j < Element::size; ++j)
      {
        Element::Vector plus = u, minus = u;
        plus[j] += e;
        minus[j] -= e;
        fd.col(j) = (residual(plus) - residual(minus)) / (2 * e);
      }
    return (fd - tangent).norm() / std::max(tangent.norm(), 1e-300);
  }
} // namespace

int
main()
{
  const Point<2>                slave(0.4, 0.1);
  const std::array<Point<2>, 2> master{{Point<2>(0, 0), Point<2>(1, 0.2)}};
  Tensor<1, 2>                  normal;
  normal[0] = -0.2;
  normal[1] = 1.0;
  const Element element(slave, master, normal);

  // c_n, c_t: the gap rates are linear in u with these gradients.
  const Element::Vector u = velocities(0.3);
  Tensor<1, 2>          relative;
  for (unsigned int d = 0; d < 2; ++d)
    relative[d] = u[d] - (1 - element.xi) * u[2 + d] - element.xi * u[4 + d];
  report("g_n = (v_s - N1 v_1 - N2 v_2).n is c_n.u",
         std::abs(element.normal_rate(u) - relative * element.normal) < 1e-14);
  report("g_t = (v_s - N1 v_1 - N2 v_2).t is c_t.u",
         std::abs(element.tangential_rate(u) - relative * element.tangent) < 1e-14);
  report("k_n and k_t vanish (the die's geometry does not move with u)",
         element.k_n.norm() == 0 && element.k_t.norm() == 0);

  FrictionLaw coulomb;
  coulomb.mu                 = 0.3;
  coulomb.tangential_penalty = 50;
  FrictionLaw tresca         = coulomb;
  tresca.kind                = FrictionLaw::Kind::tresca;
  tresca.shear_bound         = 0.7;
  FrictionLaw regularised    = coulomb;
  regularised.kind           = FrictionLaw::Kind::regularised_coulomb;
  regularised.regularisation_velocity = 0.4;

  const double omega_n = 20, normal_force = -4.0;
  struct Case
  {
    const char *   name;
    FrictionLaw    law;
    ContactStatus  status;
  };
  const Case cases[] = {{"Coulomb stick", coulomb, ContactStatus::stick},
                        {"Coulomb slip", coulomb, ContactStatus::slip},
                        {"Tresca slip", tresca, ContactStatus::slip},
                        {"regularised Coulomb", regularised, ContactStatus::slip}};
  for (const auto &c : cases)
    {
      const double sign = element.tangential_rate(u) >= 0 ? 1. : -1.;
      // Penalty normal: F_n = -omega_n g_n (the slave penetrates: g_n > 0 here).
      const auto penalty = [&](const Element::Vector &x) {
        return element.penalty(x, omega_n, true, c.law, c.status, sign).residual;
      };
      const auto r = element.penalty(u, omega_n, true, c.law, c.status, sign);
      report(std::string(c.name) + ", penalty normal: tangent matches finite differences",
             element.normal_rate(u) > 0 && tangent_error(penalty, r.tangent, u) < 1e-7);

      // Given normal force (active set): tangent in u, and dR/dF_n.
      const auto given = [&](const Element::Vector &x) {
        return element.friction_part(x, normal_force, c.law, c.status, sign).residual;
      };
      const auto g = element.friction_part(u, normal_force, c.law, c.status, sign);
      const double e = 1e-6;
      const Element::Vector d_normal =
        (element.friction_part(u, normal_force + e, c.law, c.status, sign).residual -
         element.friction_part(u, normal_force - e, c.law, c.status, sign).residual) /
        (2 * e);
      report(std::string(c.name) + ", given normal force: tangent and dR/dF_n match finite differences",
             tangent_error(given, g.tangent, u) < 1e-7 &&
               (d_normal - g.d_residual_d_normal_force).norm() <= 1e-7 * std::max(d_normal.norm(), 1.));
    }

  // Slip sits on the cone, opposite to the slip; stick is the paper's penalty.
  const double g_t   = element.tangential_rate(u);
  const auto   slip  = Element::friction(coulomb, ContactStatus::slip, g_t > 0 ? 1 : -1, g_t, normal_force);
  const auto   stick = Element::friction(coulomb, ContactStatus::stick, 1, g_t, normal_force);
  report("slip: |F_t| = mu |F_n|, opposing the slip",
         std::abs(std::abs(slip.force) - 0.3 * 4.0) < 1e-14 && slip.force * g_t < 0);
  report("stick: F_t = -omega_t g_t", std::abs(stick.force + 50 * g_t) < 1e-14);

  // The decision: a trial force inside the cone sticks, outside slips
  // against the trial force; a slipping node whose velocity reverses sticks.
  const double c = 1;
  report("small trial force: stick",
         Element::decide(coulomb, 0.5, normal_force, 0., c).first == ContactStatus::stick);
  const auto fast = Element::decide(coulomb, 5., normal_force, 0., c);
  report("large slip rate: slip in its direction", fast.first == ContactStatus::slip && fast.second == 1.);
  const auto reverse = Element::decide(coulomb, -0.5, normal_force, -1.2, c);
  report("slipping at +, velocity reverses a little: stick", reverse.first == ContactStatus::stick);
  report("no normal force, no friction bound: slip",
         Element::decide(coulomb, 0.5, 0., 0., c).first == ContactStatus::slip);
}
