// The one place where the flow's cell terms and the contact's node terms join into one linear system.
#ifndef dieflow_system_assembler_h
#define dieflow_system_assembler_h

#include <dieflow/contact/contact_set.h>
#include <dieflow/flow/flow_assembler.h>
#include <dieflow/solvers/linearization.h>
#include <dieflow/solvers/mixed_penalty.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

namespace dieflow
{
  /// What one assembly of flow and contact did.
  struct AssemblyInfo
  {
    /// Contact terms were assembled.
    bool contact = false;
    /// The Jacobian is symmetric (no slipping friction's row transformation
    /// or non-symmetric element tangent).
    bool symmetric = true;
    /// Contact elements whose friction (tangential) terms were evaluated.
    unsigned int friction_terms = 0;
  };

  /**
   * The linearised system of flow and contact at a velocity v, with the
   * contact states frozen (ContactSet::update() decides them between
   * assemblies): the flow's cell terms (FlowAssembler) with the row
   * transformations T = I + b m^T of the slipping contact nodes (the exact
   * linearisation of a Coulomb friction force that depends on the normal
   * reaction m.R_flow), then the contact elements' own residuals and
   * tangents (the slave's block: the die is rigid), condensed with the
   * homogeneous update constraints:
   *   J du = -R,  R = T R_flow(v) + (R_c - b F_n).
   * The unconstrained flow residual R_flow(v) of the last assembly is kept:
   * its entries at constrained dofs are the reactions that the relative
   * residual and the round-off bound measure against.
   *
   * It reads the dof handler, the constraints, the flow assembler and the
   * contact set it is given (the problem's, or the goal estimate's dual
   * problem's on a richer space) and writes only into its arguments and
   * its record of the last assembly.
   */
  template <int dim>
  class SystemAssembler
  {
  public:
    /// @p row_sums: on P > 1, how J is summed into each process's own rows
    /// (its pattern RowSums::reinit()'s; where only the linear solvers read
    /// J), or null for J's sums in every row (a pattern of all rows).
    SystemAssembler(const DoFHandler<dim> &          dof_handler,
                    const AffineConstraints<double> &update_constraints,
                    const FlowAssembler<dim> &       flow,
                    const ContactSet<dim> &          contact,
                    const processes::RowSums *       row_sums = nullptr);

    /**
     * J (if @p matrix) and -R at @p v into @p minus_residual, condensed;
     * with terms.mixed, the penalty's blocks apart (see
     * FlowAssembler::assemble_system()). Counts into counts().
     */
    AssemblyInfo
    assemble(const Vector<double> &   v,
             const FlowTerms<dim> &   terms,
             const Linearization      linearization,
             SparseMatrix<double> *   matrix,
             Vector<double> &         minus_residual);

    /// The same with the flow terms of @p flow_assembler (the Newtonian start's
    /// own material), counted alike.
    AssemblyInfo
    assemble(const FlowAssembler<dim> &flow_assembler,
             const Vector<double> &    v,
             const FlowTerms<dim> &    terms,
             const Linearization       linearization,
             SparseMatrix<double> *    matrix,
             Vector<double> &          minus_residual);

    /// R_flow(v) of the last assembly, unconstrained (reactions at the constrained dofs).
    const Vector<double> &
    raw_residual() const
    {
      return raw;
    }

    /// ||R|| / ||reactions||: @p minus_residual (condensed) against the
    /// reactions of the last assembly (0 for a zero residual).
    double
    relative_residual(const Vector<double> &minus_residual) const;

    /**
     * eps || |J| |v| || over the free rows, relative to the reactions of the
     * last assembly: the round-off floor of the relative residual (Higham's
     * bound for a computed residual, |fl(J v) - J v| <= eps |J| |v| per
     * row), at most 1e-4 (beyond it the reactions themselves are round-off
     * and the relative residual means nothing). @p mixed: the mixed form's
     * blocks, whose penalty term |B^T| lambda |M^-1| |B| |v| the matrix A
     * lacks.
     */
    double
    roundoff_bound(const SparseMatrix<double> &matrix, const Vector<double> &v, const MixedPenalty<dim> *mixed) const;

    /// The flow residual at the nodes (the reactions the contact states are
    /// judged from), hanging nodes condensed with @p hanging_node_constraints.
    Vector<double>
    nodal_flow_residual(const Vector<double> &           v,
                        const FlowTerms<dim> &           terms,
                        const AffineConstraints<double> &hanging_node_constraints) const;

    /// Assemblies with contact terms, and contact elements with friction terms evaluated, since reset_counts().
    struct Counts
    {
      unsigned int contact_assemblies = 0;
      unsigned int friction_terms     = 0;
    };
    const Counts &
    counts() const
    {
      return assembly_counts;
    }
    void
    reset_counts()
    {
      assembly_counts = Counts();
    }

  private:
    const DoFHandler<dim> &          dof_handler;
    const AffineConstraints<double> &update_constraints;
    const FlowAssembler<dim> &       flow;
    const ContactSet<dim> &          contact;
    const processes::RowSums *       row_sums;
    Vector<double>                   raw;
    Counts                           assembly_counts;
  };
} // namespace dieflow

#endif
