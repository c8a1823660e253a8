// The paper's contact element in velocity form: a node against a die facet, its gap rates, the friction laws, stick or slip, and its forces.
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
    const Tensor<1, dim> edge = master[1] - master[0];
    const Tensor<1, dim> to_slave = slave - master[0];
    if constexpr (dim == 2)
      {
        tangents[0][0]       = -normal[1];
        tangents[0][1]       = normal[0];
        const double xi      = (to_slave * edge) / edge.norm_square();
        master_weights       = {{1. - xi, xi}};
      }
    else
      {
        // t_1 along the edge 1-2 in the plane normal to n; t_2 = n x t_1.
        tangents[0] = edge - (edge * normal) * normal;
        tangents[0] /= tangents[0].norm();
        tangents[1] = dealii::cross_product_3d(normal, tangents[0]);
        // Barycentric coordinates of the slave's projection on the triangle.
        const Tensor<1, dim> other = master[2] - master[0];
        const double         a11 = edge * edge, a12 = edge * other, a22 = other * other;
        const double         b1 = to_slave * edge, b2 = to_slave * other;
        const double         det = a11 * a22 - a12 * a12;
        const double         xi  = (b1 * a22 - b2 * a12) / det;
        const double         eta = (a11 * b2 - a12 * b1) / det;
        master_weights           = {{1. - xi - eta, xi, eta}};
      }
    c_n.setZero();
    c_t.setZero();
    for (int a = 0; a < n_nodes; ++a)
      {
        const double N = (a == 0) ? 1. : -master_weights[a - 1];
        for (int d = 0; d < dim; ++d)
          {
            c_n[a * dim + d] = N * normal[d];
            for (int i = 0; i < n_tangents; ++i)
              c_t(a * dim + d, i) = N * tangents[i][d];
          }
      }
  }



  template <int dim>
  Tensor<1, dim>
  ContactElement<dim>::in_space(const Slip &a) const
  {
    Tensor<1, dim> x;
    for (int i = 0; i < n_tangents; ++i)
      x += a[i] * tangents[i];
    return x;
  }



  template <int dim>
  typename ContactElement<dim>::Slip
  ContactElement<dim>::in_tangent_plane(const Tensor<1, dim> &a) const
  {
    Slip x;
    for (int i = 0; i < n_tangents; ++i)
      x[i] = a * tangents[i];
    return x;
  }



  namespace
  {
    /// a / |a|, or @p fallback for a = 0.
    template <typename Slip>
    Slip
    unit_or(const Slip &a, const Slip &fallback)
    {
      const double norm = a.norm();
      return norm > 0 ? Slip(a / norm) : fallback;
    }
  } // namespace



  template <int dim>
  std::pair<ContactStatus, typename ContactElement<dim>::Slip>
  ContactElement<dim>::decide(const FrictionLaw &law,
                              const Slip &       slip_rate,
                              const double       normal_force,
                              const Slip &       friction_force,
                              const double       c)
  {
    const Slip first = Slip::Unit(0);
    switch (law.kind)
      {
        case FrictionLaw::Kind::coulomb:
        case FrictionLaw::Kind::tresca:
          {
            const double bound = law.bound(normal_force);
            const Slip trial = friction_force - c * slip_rate;
            // Without a bound (no friction, no pressure) nothing can stick.
            return {bound > 0 && trial.norm() <= bound ? ContactStatus::stick : ContactStatus::slip,
                    unit_or<Slip>(-trial, first)};
          }
        case FrictionLaw::Kind::regularised_coulomb:
          return {slip_rate.norm() <= law.regularisation_velocity ? ContactStatus::stick : ContactStatus::slip,
                  unit_or<Slip>(slip_rate, first)};
      }
    return {ContactStatus::slip, first};
  }



  template <int dim>
  typename ContactElement<dim>::Friction
  ContactElement<dim>::semismooth_slip(const FrictionLaw &law, const Slip &slip_rate, const double normal_force)
  {
    Slip lambda, g_k;
    for (int i = 0; i < n_tangents; ++i)
      {
        lambda[i] = law.multiplier.force[i];
        g_k[i]    = law.multiplier.rate[i];
      }
    const double c = law.multiplier.constant;
    const Slip   q = lambda - c * g_k; // never zero (ContactSet::law_of())
    Friction     f;
    const Slip       q_hat = q / q.norm();
    const double     a     = std::min(law.multiplier.bound / q.norm(), 1. - 1e-3);
    const SlipMatrix P     = SlipMatrix::Identity() - q_hat * q_hat.transpose();
    f.d_force_d_rate       = -c * a / (1 - a) * P;
    f.force = law.multiplier.bound * q_hat - a / (1 - a) * (P * lambda) + f.d_force_d_rate * (slip_rate - g_k);
    if (law.kind == FrictionLaw::Kind::coulomb)
      {
        // b = mu |F_n|: no friction where the die pulls (F_n > 0).
        f.force += q_hat * (law.bound(normal_force) - law.multiplier.bound);
        f.d_force_d_normal_force = -law.mu * q_hat;
      }
    return f;
  }



  template <int dim>
  typename ContactElement<dim>::Friction
  ContactElement<dim>::friction(const FrictionLaw & law,
                                const ContactStatus status,
                                const Slip &        direction,
                                const Slip &        slip_rate,
                                const double        normal_force)
  {
    Friction f;
    if (law.frictionless() || status == ContactStatus::separated)
      return f;
    const SlipMatrix identity = SlipMatrix::Identity();
    const double     rate     = slip_rate.norm();
    if (law.kind == FrictionLaw::Kind::regularised_coulomb)
      {
        // F_t = mu F_n (2/pi) atan(|g_t|/v0) s: opposes the slip since F_n <= 0;
        // none where the normal force pulls (F_n > 0), as for Coulomb below:
        // there it would drive the slip.
        if (normal_force >= 0)
          return f;
        const double v0    = law.regularisation_velocity;
        const Slip   s     = unit_or<Slip>(slip_rate, direction);
        const double shape = 2. / M_PI * std::atan(rate / v0);
        const double slope = 2. / M_PI / (v0 * (1. + std::pow(rate / v0, 2)));
        f.force            = law.mu * normal_force * shape * s;
        // d(shape s)/dg = slope s s^T + shape/|g| (I - s s^T); shape/|g| -> slope at 0.
        const double secant      = rate > 0 ? shape / rate : slope;
        f.d_force_d_rate         = law.mu * normal_force * (slope * s * s.transpose() + secant * (identity - s * s.transpose()));
        f.d_force_d_normal_force = law.mu * shape * s;
        return f;
      }
    if (status == ContactStatus::stick)
      {
        f.force          = -law.tangential_penalty * slip_rate;
        f.d_force_d_rate = -law.tangential_penalty * identity;
        return f;
      }
    // Slip in 3D with a carried friction force: the semismooth method.
    if (dim == 3 && law.multiplier.constant > 0)
      return law.kind == FrictionLaw::Kind::coulomb && normal_force >= 0 ? f : semismooth_slip(law, slip_rate, normal_force);
    // Otherwise the direction follows g_t in 3D (with its derivative); in
    // 2D it is the state's sign, constant between state updates.
    const bool live = dim == 3 && rate > law.slip_floor && rate > 0;
    const Slip s    = live ? Slip(slip_rate / rate) : direction;
    const SlipMatrix d_direction = live ? SlipMatrix((identity - s * s.transpose()) / rate) : SlipMatrix::Zero();
    if (law.kind == FrictionLaw::Kind::tresca)
      {
        f.force          = -law.shear_bound * s;
        f.d_force_d_rate = -law.shear_bound * d_direction;
      }
    else if (normal_force < 0)
      {
        // Coulomb: F_t = -mu |F_n| s = mu F_n s; no friction where the
        // normal force pulls (F_n > 0).
        f.force                  = law.mu * normal_force * s;
        f.d_force_d_rate         = law.mu * normal_force * d_direction;
        f.d_force_d_normal_force = law.mu * s;
      }
    return f;
  }



  template <int dim>
  typename ContactElement<dim>::Result
  ContactElement<dim>::friction_part(const Vector &      u,
                                     const double        normal_force,
                                     const FrictionLaw & law,
                                     const ContactStatus status,
                                     const Slip &        direction) const
  {
    const Friction f = friction(law, status, direction, tangential_rate(u), normal_force);
    Result         r;
    r.normal_force              = normal_force;
    r.friction_force            = f.force;
    r.residual                  = -(c_t * f.force);
    r.tangent                   = -(c_t * f.d_force_d_rate * c_t.transpose());
    r.d_residual_d_normal_force = -(c_t * f.d_force_d_normal_force);
    return r;
  }



  template <int dim>
  typename ContactElement<dim>::Result
  ContactElement<dim>::penalty(const Vector &      u,
                               const double        omega_n,
                               const bool          in_contact,
                               const FrictionLaw & law,
                               const ContactStatus status,
                               const Slip &        direction) const
  {
    Result r;
    r.residual.setZero();
    r.tangent.setZero();
    r.d_residual_d_normal_force.setZero();
    if (!in_contact)
      return r;
    const double   normal_force = -omega_n * normal_rate(u);
    const Friction f            = friction(law, status, direction, tangential_rate(u), normal_force);
    r.normal_force              = normal_force;
    r.friction_force            = f.force;
    r.residual                  = -(normal_force * c_n + c_t * f.force);
    // dF_n/du = -omega_n c_n; dF_t/du = (dF_t/dg_t) C_t^T + (dF_t/dF_n) dF_n/du.
    r.tangent = omega_n * c_n * c_n.transpose() - c_t * f.d_force_d_rate * c_t.transpose() +
                omega_n * (c_t * f.d_force_d_normal_force) * c_n.transpose();
    r.d_residual_d_normal_force = -(c_n + c_t * f.d_force_d_normal_force);
    return r;
  }

  template class ContactElement<2>;
  template class ContactElement<3>;
} // namespace dieflow
