// The paper's contact element in velocity form: a node against a die facet, its gap rates, the friction laws, stick or slip, and its forces.
#ifndef dieflow_contact_element_h
#define dieflow_contact_element_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>

namespace dieflow
{
  using dealii::Point;
  using dealii::Tensor;

  /// Contact state of a node (and of each of its wall directions).
  enum class ContactStatus
  {
    separated = 0,
    stick     = 1,
    slip      = 2
  };

  /// The friction law of one contact element.
  struct FrictionLaw
  {
    enum class Kind
    {
      /// |F_t| <= mu |F_n|, stick below, slip at the bound (eq. (6)).
      coulomb,
      /// |F_t| <= m k w: a constant shear stress bound times the node's weight.
      tresca,
      /// F_t = mu F_n (2/pi) atan(g_t / v0): no stick, smooth.
      regularised_coulomb
    };
    Kind   kind = Kind::coulomb;
    double mu   = 0;
    /// Tresca: the bound m k w of the tangential force (force units).
    double shear_bound = 0;
    /// omega_t: the stick force per unit slip rate (the paper's tangential
    /// penalty, eqs. (12), (16)).
    double tangential_penalty = 0;
    /// v0 of the regularised law.
    double regularisation_velocity = 1;
    /// 3D: below this slip rate (velocity units) the slip direction is the
    /// state's, not g_t / |g_t|, whose derivative grows as 1 / |g_t|.
    double slip_floor = 0;
    /// 3D slip by the semismooth Newton method (ContactElement::friction()):
    /// the friction force lambda carried from the last state update, the
    /// slip rate g_k and the bound b_k it was linearised at (tangent basis),
    /// and the constant c of the trial lambda - c g. constant = 0: none (the
    /// slip direction is g / |g|).
    struct SlipMultiplier
    {
      double force[2] = {0, 0};
      double rate[2]  = {0, 0};
      double bound    = 0;
      double constant = 0;
    } multiplier;

    bool
    frictionless() const
    {
      return kind == Kind::tresca ? shear_bound == 0 : mu == 0;
    }

    /// The bound of |F_t| for Coulomb (mu |F_n|, zero where the die pulls,
    /// F_n > 0) and Tresca (m k w).
    double
    bound(const double normal_force) const
    {
      return kind == Kind::tresca ? shear_bound : mu * std::max(-normal_force, 0.);
    }
  };

  /**
   * The paper's contact element in velocity form: a slave node s of the
   * metal's boundary against a master facet of the die, the segment 1-2 in
   * 2D (the three-node element) and the triangle 1-2-3 in 3D (the four-node
   * element). With the unknowns u = (v_s, v_1, .., v_dim) (the master
   * velocities are zero for a fixed die; a moving die gives them), the gap
   * rates are
   *   g_n = (v_s - sum_a N_a v_a) . n,   g_t,i = (v_s - sum_a N_a v_a) . t_i,
   * with N_a the master's shape functions at the slave's projection
   * (N = (1 - xi, xi) on the segment, barycentric on the triangle), n the
   * outward normal of the metal and t_i an orthonormal tangent basis:
   * t = (-n_y, n_x) in 2D; in 3D t_1 along the edge 1-2 and t_2 = n x t_1
   * (the paper's tau along 1-3, made orthogonal to t_1 so that the cone
   * sqrt(Sigma_t^2 + Sigma_tau^2) <= mu |Sigma_n| is isotropic). Their
   * variations are c_n = dg_n/du = (n, -N_1 n, ..) and the columns of C_t.
   * In the steady, Eulerian velocity problem the die's geometry does not
   * move with u, so n, t_i and N_a do not depend on u and the second
   * variations of the gaps vanish.
   *
   * Forces on the slave are F_n n + sum_i F_t,i t_i (F_n <= 0 pushes into
   * the metal); the element's residual, as internal minus external force, is
   *   R_c = -(F_n c_n + C_t F_t)                          (eq. (18)).
   * Stick: F_t = -omega_t g_t (eqs. (12), (16)). Slip: F_t = -mu |F_n| s
   * with s the slip direction in the tangent plane, s = g_t / |g_t|; its
   * derivative mu F_n (I - s s^T) / |g_t| is part of the tangent in 3D and
   * vanishes in 2D, where s = +-1 is the frozen sign of the state. The
   * dependence of F_t on F_n is the non-symmetric part of the linearisation
   * (the paper's SL1, SL2 terms).
   */
  template <int dim>
  class ContactElement
  {
    static_assert(dim == 2 || dim == 3, "The contact element is two- or three-dimensional.");

  public:
    static constexpr int n_nodes    = dim + 1;
    static constexpr int size       = n_nodes * dim;
    static constexpr int n_tangents = dim - 1;
    using Vector                    = Eigen::Matrix<double, size, 1>;
    using Matrix                    = Eigen::Matrix<double, size, size>;
    /// A tangential quantity (slip rate, friction force, slip direction) in
    /// the tangent basis t_i.
    using Slip       = Eigen::Matrix<double, n_tangents, 1>;
    using SlipMatrix = Eigen::Matrix<double, n_tangents, n_tangents>;

    ContactElement(const Point<dim> &                 slave,
                   const std::array<Point<dim>, dim> &master,
                   const Tensor<1, dim> &             outward_normal);

    /// The friction force F_t and its derivatives for a given state.
    struct Friction
    {
      Slip       force                  = Slip::Zero();
      SlipMatrix d_force_d_rate         = SlipMatrix::Zero();
      Slip       d_force_d_normal_force = Slip::Zero();
    };

    /**
     * Stick or slip (and the slip direction) from the paper's test
     * |F_t^trial| <= mu |F_n| (step (iii b)), with the semismooth (augmented)
     * trial force F_t^trial = F_t - c g_t of the current friction force F_t
     * and slip rate g_t (Alart-Curnier; Hueber, Stadler, Wohlmuth 2008). A
     * slipping node whose velocity reverses within c|g_t| < 2 mu|F_n| sticks;
     * with F_t = -omega_t g_t (a sticking node) it is the paper's trial
     * -(omega_t + c) g_t. The slip direction opposes the trial force.
     */
    static std::pair<ContactStatus, Slip>
    decide(const FrictionLaw &law,
           const Slip &       slip_rate,
           const double       normal_force,
           const Slip &       friction_force,
           const double       c);

    /**
     * F_t in the given state. @p direction: the state's slip direction, the
     * direction of slip in 2D; in 3D only where |g_t| is below the law's
     * slip floor (a node at rest has no direction of its own).
     *
     * 3D slip with a carried multiplier (law.multiplier): the semismooth
     * Newton method of Hueber, Stadler and Wohlmuth (SIAM J. Sci. Comput. 30
     * (2008) 572) on (v, lambda), the friction force lambda an unknown of
     * each node, eliminated there. Slip means C(lambda, g) = lambda - b q/|q|
     * = 0 with q = lambda - c g outside the cone (|q| > b = mu |F_n|, the
     * paper's slip condition (6)). Linearised at (lambda, g_k, b_k), with
     * a = b_k/|q|, q^ = q/|q|, P = I - q^ q^T:
     *   F_t = b_k q^ - a/(1-a) P lambda - c a/(1-a) P (g - g_k) + q^ (b - b_k),
     * the force lambda + d lambda of the Newton step, which the next state
     * update carries as lambda. At its fixed point C = 0: |lambda| = b and g
     * is opposite to lambda (slip against the friction force). The stiffness
     * across the slip, c a/(1-a), stays bounded while the node slips (a < 1;
     * capped at a = 0.999), where the derivative of g/|g|, b/|g|, grows
     * without bound as the slip rate vanishes: nodes slipping slowly then
     * traded stick and slip without end (doc/three-dimensional.md).
     */
    static Friction
    friction(const FrictionLaw & law,
             const ContactStatus status,
             const Slip &        direction,
             const Slip &        slip_rate,
             const double        normal_force);

    /// friction() of a slipping 3D node with a carried multiplier.
    static Friction
    semismooth_slip(const FrictionLaw &law, const Slip &slip_rate, const double normal_force);

    struct Result
    {
      Vector residual;
      Matrix tangent;
      /// dR_c / dF_n at fixed u: how the residual follows the normal force.
      Vector d_residual_d_normal_force;
      double normal_force   = 0;
      Slip   friction_force = Slip::Zero();
    };

    /**
     * Friction only, at a given normal force F_n (the active-set normal
     * enforcement, where F_n is the reaction of the constraint v.n = 0):
     * R_c = -C_t F_t, dR_c/du = -C_t (dF_t/dg_t) C_t^T, and
     * dR_c/dF_n = -C_t dF_t/dF_n, which the caller chains with dF_n/du.
     */
    Result
    friction_part(const Vector &      u,
                  const double        normal_force,
                  const FrictionLaw & law,
                  const ContactStatus status,
                  const Slip &        direction) const;

    /**
     * Penalty normal enforcement (the paper's omega_n, eq. (20)): F_n =
     * -omega_n g_n where the slave penetrates (g_n > 0, @p in_contact),
     * zero otherwise, and friction at that F_n with the full linearisation
     *   dR_c/du = omega_n c_n c_n^T - C_t (dF_t/dg_t) C_t^T
     *             + omega_n C_t (dF_t/dF_n) c_n^T.
     */
    Result
    penalty(const Vector &      u,
            const double        omega_n,
            const bool          in_contact,
            const FrictionLaw & law,
            const ContactStatus status,
            const Slip &        direction) const;

    double
    normal_rate(const Vector &u) const
    {
      return c_n.dot(u);
    }
    Slip
    tangential_rate(const Vector &u) const
    {
      return c_t.transpose() * u;
    }
    /// sum_i a_i t_i: a tangential quantity as a vector in space.
    Tensor<1, dim>
    in_space(const Slip &a) const;
    /// The components of a vector along the tangents t_i.
    Slip
    in_tangent_plane(const Tensor<1, dim> &a) const;

    Tensor<1, dim>                       normal;
    std::array<Tensor<1, dim>, n_tangents> tangents;
    /// The master's shape functions N_a at the slave's projection.
    std::array<double, dim> master_weights;
    Vector                  c_n;
    Eigen::Matrix<double, size, n_tangents> c_t;
  };
} // namespace dieflow

#endif
