#ifndef dieflow_contact_element_h
#define dieflow_contact_element_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <Eigen/Dense>

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

    bool
    frictionless() const
    {
      return kind == Kind::tresca ? shear_bound == 0 : mu == 0;
    }
  };

  /**
   * The paper's three-node contact element in velocity form (2D): a slave
   * node s of the metal's boundary and a master segment 1-2 of the die
   * surface. With the unknowns u = (v_s, v_1, v_2) (the master velocities
   * are zero for a rigid, fixed die, but the element is written for a moving
   * master so that the four-node 3D element can follow), the gap rates are
   *   g_n = (v_s - N_1 v_1 - N_2 v_2) . n,  g_t = (v_s - N_1 v_1 - N_2 v_2) . t,
   * with N_1 = 1 - xi, N_2 = xi at the slave's projection xi on the segment,
   * n the outward normal of the metal and t = (-n_y, n_x). Their variations
   * are c_n = dg_n/du = (n, -N_1 n, -N_2 n) and c_t likewise. In the steady,
   * Eulerian velocity problem the die geometry does not move with u, so
   * n, t and xi do not depend on u and the second variations k_n, k_t
   * vanish (they would not for a deformable master).
   *
   * Forces on the slave are F_n n + F_t t (F_n <= 0 pushes into the metal);
   * the element's residual, as internal minus external force, is
   *   R_c = -(F_n c_n + F_t c_t)                       (eq. (18)).
   * Stick: F_t = -omega_t g_t. Slip: F_t = -mu |F_n| sign(g_t); the
   * dependence of F_t on F_n is the non-symmetric part of the linearisation
   * (the paper's SL1, SL2 terms).
   */
  template <int dim>
  class ContactElement
  {
    static_assert(dim == 2, "The contact element is two-dimensional (slave + master segment).");

  public:
    static constexpr int n_nodes = dim + 1;
    static constexpr int size    = n_nodes * dim;
    using Vector                 = Eigen::Matrix<double, size, 1>;
    using Matrix                 = Eigen::Matrix<double, size, size>;

    ContactElement(const Point<dim> &                 slave,
                   const std::array<Point<dim>, dim> &master,
                   const Tensor<1, dim> &             outward_normal);

    /// The friction force F_t and its derivatives for a given state.
    struct Friction
    {
      double force          = 0;
      double d_force_d_rate = 0;
      double d_force_d_normal_force = 0;
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
    static std::pair<ContactStatus, double>
    decide(const FrictionLaw &law,
           const double       slip_rate,
           const double       normal_force,
           const double       friction_force,
           const double       c);

    /// F_t in the given state (@p sign: the frozen slip direction).
    static Friction
    friction(const FrictionLaw & law,
             const ContactStatus status,
             const double        sign,
             const double        slip_rate,
             const double        normal_force);

    struct Result
    {
      Vector residual;
      Matrix tangent;
      /// dR_c / dF_n at fixed u: how the residual follows the normal force.
      Vector        d_residual_d_normal_force;
      double        normal_force   = 0;
      double        friction_force = 0;
    };

    /**
     * Friction only, at a given normal force F_n (the active-set normal
     * enforcement, where F_n is the reaction of the constraint v.n = 0):
     * R_c = -F_t c_t, dR_c/du = -(dF_t/dg_t) c_t c_t^T, and
     * dR_c/dF_n = -(dF_t/dF_n) c_t, which the caller chains with dF_n/du.
     */
    Result
    friction_part(const Vector &      u,
                  const double        normal_force,
                  const FrictionLaw & law,
                  const ContactStatus status,
                  const double        sign) const;

    /**
     * Penalty normal enforcement (the paper's omega_n, eq. (20)): F_n =
     * -omega_n g_n where the slave penetrates (g_n > 0, @p in_contact),
     * zero otherwise, and friction at that F_n with the full linearisation
     *   dR_c/du = omega_n c_n c_n^T - (dF_t/dg_t) c_t c_t^T
     *             + omega_n (dF_t/dF_n) c_t c_n^T.
     */
    Result
    penalty(const Vector &      u,
            const double        omega_n,
            const bool          in_contact,
            const FrictionLaw & law,
            const ContactStatus status,
            const double        sign) const;

    double
    normal_rate(const Vector &u) const
    {
      return c_n.dot(u);
    }
    double
    tangential_rate(const Vector &u) const
    {
      return c_t.dot(u);
    }

    Tensor<1, dim> normal;
    Tensor<1, dim> tangent;
    /// Projection of the slave on the master segment, 0 at vertex 1.
    double xi;
    Vector c_n;
    Vector c_t;
    /// Second variations: zero for a die whose geometry does not move with u.
    Matrix k_n;
    Matrix k_t;
  };
} // namespace dieflow

#endif
