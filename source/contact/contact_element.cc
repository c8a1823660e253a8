#include <dieflow/contact/contact_element.h>

#include <cmath>

namespace dieflow
{
  template <int dim>
  ContactElement<dim>::ContactElement(const Point<dim> &                 slave,
                                      const std::array<Point<dim>, dim> &master,
                                      const Tensor<1, dim> &             outward_normal)
    : normal(outward_normal / outward_normal.norm())
  {
    tangent[0]               = -normal[1];
    tangent[1]               = normal[0];
    const Tensor<1, dim> seg = master[1] - master[0];
    xi                       = ((slave - master[0]) * seg) / seg.norm_square();
    const double N[n_nodes]  = {1., -(1. - xi), -xi};
    for (int a = 0; a < n_nodes; ++a)
      for (int d = 0; d < dim; ++d)
        {
          c_n[a * dim + d] = N[a] * normal[d];
          c_t[a * dim + d] = N[a] * tangent[d];
        }
    k_n.setZero();
    k_t.setZero();
  }



  template <int dim>
  std::pair<ContactStatus, double>
  ContactElement<dim>::decide(const FrictionLaw &law,
                              const double       slip_rate,
                              const double       normal_force,
                              const double       friction_force,
                              const double       c)
  {
    switch (law.kind)
      {
        case FrictionLaw::Kind::coulomb:
        case FrictionLaw::Kind::tresca:
          {
            const double bound = (law.kind == FrictionLaw::Kind::tresca) ?
                                   law.shear_bound :
                                   law.mu * std::max(-normal_force, 0.);
            const double trial = friction_force - c * slip_rate;
            const double sign  = (trial <= 0) ? 1. : -1.;
            // Without a bound (no friction, no pressure) nothing can stick.
            return {bound > 0 && std::abs(trial) <= bound ? ContactStatus::stick : ContactStatus::slip, sign};
          }
        case FrictionLaw::Kind::regularised_coulomb:
          return {std::abs(slip_rate) <= law.regularisation_velocity ? ContactStatus::stick :
                                                                       ContactStatus::slip,
                  slip_rate >= 0 ? 1. : -1.};
      }
    return {ContactStatus::slip, 1.};
  }



  template <int dim>
  typename ContactElement<dim>::Friction
  ContactElement<dim>::friction(const FrictionLaw & law,
                                const ContactStatus status,
                                const double        sign,
                                const double        slip_rate,
                                const double        normal_force)
  {
    Friction f;
    if (law.frictionless() || status == ContactStatus::separated)
      return f;
    if (law.kind == FrictionLaw::Kind::regularised_coulomb)
      {
        // F_t = mu F_n (2/pi) atan(g_t/v0): opposes the slip since F_n <= 0.
        const double v0    = law.regularisation_velocity;
        const double shape = 2. / M_PI * std::atan(slip_rate / v0);
        f.force            = law.mu * normal_force * shape;
        f.d_force_d_rate   = law.mu * normal_force * 2. / M_PI / (v0 * (1. + std::pow(slip_rate / v0, 2)));
        f.d_force_d_normal_force = law.mu * shape;
        return f;
      }
    if (status == ContactStatus::stick)
      {
        f.force          = -law.tangential_penalty * slip_rate;
        f.d_force_d_rate = -law.tangential_penalty;
        return f;
      }
    if (law.kind == FrictionLaw::Kind::tresca)
      f.force = -law.shear_bound * sign;
    else
      {
        // Slip: F_t = -mu |F_n| sign(g_t) = mu F_n sign for F_n <= 0; no
        // friction where the normal force pulls (F_n > 0).
        if (normal_force < 0)
          {
            f.force                  = law.mu * normal_force * sign;
            f.d_force_d_normal_force = law.mu * sign;
          }
      }
    return f;
  }



  template <int dim>
  typename ContactElement<dim>::Result
  ContactElement<dim>::friction_part(const Vector &      u,
                                     const double        normal_force,
                                     const FrictionLaw & law,
                                     const ContactStatus status,
                                     const double        sign) const
  {
    const Friction f = friction(law, status, sign, tangential_rate(u), normal_force);
    Result         r;
    r.normal_force              = normal_force;
    r.friction_force            = f.force;
    r.residual                  = -f.force * c_t;
    r.tangent                   = -f.d_force_d_rate * c_t * c_t.transpose() - f.force * k_t;
    r.d_residual_d_normal_force = -f.d_force_d_normal_force * c_t;
    return r;
  }



  template <int dim>
  typename ContactElement<dim>::Result
  ContactElement<dim>::penalty(const Vector &      u,
                               const double        omega_n,
                               const bool          in_contact,
                               const FrictionLaw & law,
                               const ContactStatus status,
                               const double        sign) const
  {
    Result r;
    r.residual.setZero();
    r.tangent.setZero();
    r.d_residual_d_normal_force.setZero();
    if (!in_contact)
      return r;
    const double   normal_force = -omega_n * normal_rate(u);
    const Friction f            = friction(law, status, sign, tangential_rate(u), normal_force);
    r.normal_force              = normal_force;
    r.friction_force            = f.force;
    r.residual                  = -(normal_force * c_n + f.force * c_t);
    // dF_n/du = -omega_n c_n; dF_t/du = (dF_t/dg_t) c_t + (dF_t/dF_n) dF_n/du.
    r.tangent = omega_n * c_n * c_n.transpose() - f.d_force_d_rate * c_t * c_t.transpose() +
                omega_n * f.d_force_d_normal_force * c_t * c_n.transpose() - normal_force * k_n -
                f.force * k_t;
    r.d_residual_d_normal_force = -(c_n + f.d_force_d_normal_force * c_t);
    return r;
  }

  template class ContactElement<2>;
} // namespace dieflow
