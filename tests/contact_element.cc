// The contact element against finite differences, in 2D (slave node +
// master segment, the paper's three-node element) and 3D (slave + master
// triangle, the four-node element), both with a moving master: its
// residual's derivative in the velocities u = (v_s, v_1, .., v_dim) must be
// its tangent, for every friction law and state, with the normal force
// either given (active set: also dR/dF_n) or from the penalty (then the
// non-symmetric SL terms). In 3D the slip direction g_t / |g_t| depends on
// u, so the tangent holds its derivative. Central differences with step
// 1e-6 |u| have a truncation error of order 1e-12 relative where the
// element is smooth (the slip rates here are far from zero): tolerance
// 1e-7. Also: c_n, C_t are the variations of the gap rates, the master
// weights interpolate the slave's projection, slip sits on the Coulomb cone
// opposite to the slip, stick below it. In 3D the semismooth slip (the
// friction force carried as a condensed unknown): its derivatives, its
// fixed point (Coulomb's slip), and its finite stiffness across the slip of
// a node just released from stick.
#include <dieflow/contact/contact_element.h>

#include "report.h"

#include <cmath>

using namespace dieflow;

namespace
{
  template <int dim>
  typename ContactElement<dim>::Vector
  velocities(const double shift)
  {
    typename ContactElement<dim>::Vector u;
    for (int i = 0; i < ContactElement<dim>::size; ++i)
      u[i] = std::sin(1.7 * i + shift) * (i < dim ? 3. : 0.5);
    return u;
  }

  // Largest relative gap between the tangent and central differences.
  template <int dim, typename Residual>
  double
  tangent_error(const Residual &                            residual,
                const typename ContactElement<dim>::Matrix &tangent,
                const typename ContactElement<dim>::Vector &u)
  {
    const double                         e = 1e-6 * u.norm();
    typename ContactElement<dim>::Matrix fd;
    for (int j = 0; j < ContactElement<dim>::size; ++j)
      {
        typename ContactElement<dim>::Vector plus = u, minus = u;
        plus[j] += e;
        minus[j] -= e;
        fd.col(j) = (residual(plus) - residual(minus)) / (2 * e);
      }
    return (fd - tangent).norm() / std::max(tangent.norm(), 1e-300);
  }

  /// A slave above a tilted master facet (segment or triangle).
  template <int dim>
  ContactElement<dim>
  element();

  template <>
  ContactElement<2>
  element<2>()
  {
    const std::array<Point<2>, 2> master{{Point<2>(0, 0), Point<2>(1, 0.2)}};
    Tensor<1, 2>                  normal;
    normal[0] = -0.2;
    normal[1] = 1.0;
    return ContactElement<2>(Point<2>(0.4, 0.1), master, normal);
  }

  template <>
  ContactElement<3>
  element<3>()
  {
    const std::array<Point<3>, 3> master{{Point<3>(0, 0, 0), Point<3>(1, 0.2, 0.1), Point<3>(0.3, 1, -0.2)}};
    // The metal lies on the side of the triangle that (1-2) x (1-3) points away from.
    const Tensor<1, 3> normal = -dealii::cross_product_3d(master[1] - master[0], master[2] - master[0]);
    return ContactElement<3>(Point<3>(0.35, 0.3, 0.2), master, normal);
  }

  template <int dim>
  void
  check()
  {
    using Element = ContactElement<dim>;
    using Slip    = typename Element::Slip;
    const std::string prefix = std::to_string(dim) + "D: ";
    const Element     e      = element<dim>();

    // c_n, C_t: the gap rates are linear in u with these gradients.
    const typename Element::Vector u = velocities<dim>(0.3);
    Tensor<1, dim>                 relative;
    double                         weight_sum = 0;
    for (unsigned int d = 0; d < dim; ++d)
      relative[d] = u[d];
    for (unsigned int a = 0; a < dim; ++a)
      {
        weight_sum += e.master_weights[a];
        for (unsigned int d = 0; d < dim; ++d)
          relative[d] -= e.master_weights[a] * u[dim * (a + 1) + d];
      }
    report(prefix + "g_n = (v_s - sum N_a v_a).n is c_n.u", std::abs(e.normal_rate(u) - relative * e.normal) < 1e-14);
    report(prefix + "g_t = (v_s - sum N_a v_a).t_i is C_t^T u",
           (e.tangential_rate(u) - e.in_tangent_plane(relative)).norm() < 1e-14);
    bool orthonormal = std::abs(e.normal.norm() - 1) < 1e-14;
    for (int i = 0; i < Element::n_tangents; ++i)
      {
        orthonormal &= std::abs(e.tangents[i].norm() - 1) < 1e-14 && std::abs(e.tangents[i] * e.normal) < 1e-14;
        for (int j = 0; j < i; ++j)
          orthonormal &= std::abs(e.tangents[i] * e.tangents[j]) < 1e-14;
      }
    report(prefix + "n and t_i are orthonormal", orthonormal);
    report(prefix + "the master weights sum to one", std::abs(weight_sum - 1) < 1e-14);

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
      const char *  name;
      FrictionLaw   law;
      ContactStatus status;
    };
    const Case cases[] = {{"Coulomb stick", coulomb, ContactStatus::stick},
                          {"Coulomb slip", coulomb, ContactStatus::slip},
                          {"Tresca slip", tresca, ContactStatus::slip},
                          {"regularised Coulomb", regularised, ContactStatus::slip}};
    const Slip direction = e.tangential_rate(u) / e.tangential_rate(u).norm();
    for (const auto &c : cases)
      {
        // Penalty normal: F_n = -omega_n g_n (the slave penetrates: g_n > 0 here).
        const auto penalty = [&](const typename Element::Vector &x) {
          return e.penalty(x, omega_n, true, c.law, c.status, direction).residual;
        };
        const auto r = e.penalty(u, omega_n, true, c.law, c.status, direction);
        report(prefix + c.name + ", penalty normal: tangent matches finite differences",
               e.normal_rate(u) > 0 && tangent_error<dim>(penalty, r.tangent, u) < 1e-7);

        // Given normal force (active set): tangent in u, and dR/dF_n.
        const auto given = [&](const typename Element::Vector &x) {
          return e.friction_part(x, normal_force, c.law, c.status, direction).residual;
        };
        const auto                     g = e.friction_part(u, normal_force, c.law, c.status, direction);
        const double                   h = 1e-6;
        const typename Element::Vector d_normal =
          (e.friction_part(u, normal_force + h, c.law, c.status, direction).residual -
           e.friction_part(u, normal_force - h, c.law, c.status, direction).residual) /
          (2 * h);
        report(prefix + c.name + ", given normal force: tangent and dR/dF_n match finite differences",
               tangent_error<dim>(given, g.tangent, u) < 1e-7 &&
                 (d_normal - g.d_residual_d_normal_force).norm() <= 1e-7 * std::max(d_normal.norm(), 1.));
      }

    // Slip sits on the cone, opposite to the slip; stick is the paper's penalty.
    const Slip g_t   = e.tangential_rate(u);
    const auto slip  = Element::friction(coulomb, ContactStatus::slip, direction, g_t, normal_force);
    const auto stick = Element::friction(coulomb, ContactStatus::stick, direction, g_t, normal_force);
    report(prefix + "slip: |F_t| = mu |F_n|, opposite to the slip",
           std::abs(slip.force.norm() - 0.3 * 4.0) < 1e-14 &&
             (slip.force / slip.force.norm() + g_t / g_t.norm()).norm() < 1e-14);
    report(prefix + "stick: F_t = -omega_t g_t", (stick.force + 50 * g_t).norm() < 1e-13);

    // The decision: a trial force inside the cone sticks, outside slips
    // against the trial force; a slipping node whose velocity reverses sticks.
    const double c     = 1;
    Slip         along = Slip::Zero();
    along[dim - 2]     = 1; // t in 2D, t_2 in 3D
    report(prefix + "small trial force: stick",
           Element::decide(coulomb, 0.5 * along, normal_force, Slip::Zero(), c).first == ContactStatus::stick);
    const auto fast = Element::decide(coulomb, 5. * along, normal_force, Slip::Zero(), c);
    report(prefix + "large slip rate: slip in its direction",
           fast.first == ContactStatus::slip && (fast.second - along).norm() < 1e-15);
    const auto reverse = Element::decide(coulomb, -0.5 * along, normal_force, -1.2 * along, c);
    report(prefix + "slipping at +, velocity reverses a little: stick", reverse.first == ContactStatus::stick);
    report(prefix + "no normal force, no friction bound: slip",
           Element::decide(coulomb, 0.5 * along, 0., Slip::Zero(), c).first == ContactStatus::slip);
    if constexpr (dim == 3)
      {
        // The cone is isotropic: a trial force of the bound's size sticks
        // in any direction of the tangent plane, one 1 % larger slips
        // against it.
        bool isotropic = true;
        for (double angle = 0; angle < 6.28; angle += 0.5)
          {
            const Slip   unit(std::cos(angle), std::sin(angle));
            const double bound = 0.3 * 4.0;
            const auto   in    = Element::decide(coulomb, Slip::Zero(), normal_force, 0.999 * bound * unit, c);
            const auto   out   = Element::decide(coulomb, Slip::Zero(), normal_force, 1.01 * bound * unit, c);
            isotropic &= in.first == ContactStatus::stick && out.first == ContactStatus::slip &&
                         (out.second + unit).norm() < 1e-14;
          }
        report(prefix + "the Coulomb cone is isotropic in the tangent plane", isotropic);

        // Slip by the semismooth Newton method, the friction force lambda
        // carried (linearised at g_k, b_k; c = 2): the friction residual's
        // tangent and dR/dF_n are its derivatives (the model is linear in g_t
        // and F_n: finite differences to round-off).
        const double b = 0.3 * 4.0, c_t = 2;
        const auto   carried = [&](FrictionLaw law, const Slip &lambda, const Slip &g_k) {
          law.multiplier.constant = c_t;
          law.multiplier.bound    = law.bound(normal_force);
          for (int i = 0; i < 2; ++i)
            {
              law.multiplier.force[i] = lambda[i];
              law.multiplier.rate[i]  = g_k[i];
            }
          return law;
        };
        for (const auto &[name, base] : {std::make_pair("Coulomb", coulomb), std::make_pair("Tresca", tresca)})
          {
            const FrictionLaw law   = carried(base, Slip(1.0, 1.0), Slip(0.2, -0.1));
            const auto        given = [&](const typename Element::Vector &x) {
              return e.friction_part(x, normal_force, law, ContactStatus::slip, direction).residual;
            };
            const auto                     g = e.friction_part(u, normal_force, law, ContactStatus::slip, direction);
            const double                   h = 1e-6;
            const typename Element::Vector d_normal =
              (e.friction_part(u, normal_force + h, law, ContactStatus::slip, direction).residual -
               e.friction_part(u, normal_force - h, law, ContactStatus::slip, direction).residual) /
              (2 * h);
            report(prefix + name + " slip, semismooth (carried force): tangent and dR/dF_n match finite differences",
                   tangent_error<dim>(given, g.tangent, u) < 1e-7 &&
                     (d_normal - g.d_residual_d_normal_force).norm() <= 1e-7 * std::max(d_normal.norm(), 1.));
          }
        // At its fixed point (lambda on the cone, the slip against it) the
        // force is lambda itself: a converged state is Coulomb's slip.
        const Slip g_k(0.3, -0.4), lambda = -b * g_k / g_k.norm();
        const auto fixed = Element::friction(carried(coulomb, lambda, g_k), ContactStatus::slip, direction, g_k,
                                             normal_force);
        report(prefix + "semismooth slip at its fixed point: F_t = lambda, |F_t| = mu |F_n| against the slip",
               (fixed.force - lambda).norm() < 1e-14);
        // A node just released from stick (at rest, its stick force 1 %
        // beyond the cone): the force is the bound along the stick force,
        // and the stiffness across it c a/(1-a), a = b/|lambda| (here 100 c),
        // is finite where g_t/|g_t| has no derivative at all.
        const Slip unit(0.6, 0.8), across(-0.8, 0.6);
        const auto released = Element::friction(carried(coulomb, 1.01 * b * unit, Slip::Zero()), ContactStatus::slip,
                                                direction, Slip::Zero(), normal_force);
        report(prefix + "semismooth slip just released: F_t = mu |F_n| along the stick force, stiffness 100 c across it",
               (released.force - b * unit).norm() < 1e-14 &&
                 std::abs(across.dot(released.d_force_d_rate * across) + 100 * c_t) < 1e-9 &&
                 (released.d_force_d_rate * unit).norm() < 1e-14);
      }
  }
} // namespace

int
main()
{
  check<2>();
  check<3>();
}
