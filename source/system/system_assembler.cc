// The one place where the flow's cell terms and the contact's node terms join into one linear system.
#include <dieflow/system/system_assembler.h>

#include <dieflow/base/processes.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dieflow
{
  template <int dim>
  SystemAssembler<dim>::SystemAssembler(const DoFHandler<dim> &          dof_handler,
                                        const AffineConstraints<double> &update_constraints,
                                        const FlowAssembler<dim> &       flow,
                                        const ContactSet<dim> &          contact,
                                        const processes::RowSums *       row_sums)
    : dof_handler(dof_handler)
    , update_constraints(update_constraints)
    , flow(flow)
    , contact(contact)
    , row_sums(row_sums)
  {}



  template <int dim>
  AssemblyInfo
  SystemAssembler<dim>::assemble(const Vector<double> &v,
                                 const FlowTerms<dim> &terms,
                                 const Linearization   linearization,
                                 SparseMatrix<double> *matrix,
                                 Vector<double> &      minus_residual)
  {
    return assemble(flow, v, terms, linearization, matrix, minus_residual);
  }



  template <int dim>
  AssemblyInfo
  SystemAssembler<dim>::assemble(const FlowAssembler<dim> &flow_assembler,
                                 const Vector<double> &    v,
                                 const FlowTerms<dim> &    terms,
                                 const Linearization       linearization,
                                 SparseMatrix<double> *    matrix,
                                 Vector<double> &          minus_residual)
  {
    std::vector<ContactContribution<dim>> contributions;
    RowTransforms                         transforms;
    AssemblyInfo                          info;
    if (!contact.empty())
      {
        info.contact        = true;
        contributions       = contact.contributions(v);
        info.friction_terms = contributions.size();
        for (const auto &c : contributions)
          {
            // The walls of an edge node each add their b m^T to one T:
            // T = I + sum_k b_k m_k^T (keeping the first alone dropped the
            // second wall's friction from the equations).
            if (c.has_row_transform)
              {
                const auto [entry, inserted] = transforms.emplace(c.dofs[0], c.row_transform);
                if (!inserted)
                  for (unsigned int a = 0; a < dim; ++a)
                    for (unsigned int b = 0; b < dim; ++b)
                      entry->second(a, b) += c.row_transform(a, b) - (a == b ? 1. : 0.);
              }
            for (unsigned int a = 0; a < dim; ++a)
              for (unsigned int b = 0; b < a; ++b)
                if (std::abs(c.tangent(a, b) - c.tangent(b, a)) > 1e-12 * c.tangent.linfty_norm())
                  info.symmetric = false;
          }
        info.symmetric = info.symmetric && transforms.empty();
      }
    if (matrix != nullptr)
      flow_assembler.assemble_system(dof_handler, v, terms, update_constraints, linearization, *matrix, minus_residual, raw,
                                     &transforms, row_sums);
    else
      flow_assembler.assemble_residual(dof_handler, v, terms, update_constraints, minus_residual, raw, &transforms);

    // A contact element's terms couple the components of its node alone
    // (the wall and Dirichlet constraints too; a hanging node is no wall
    // node): where J is summed into own rows, the node's owner adds them.
    const bool             own_rows_only = matrix != nullptr && row_sums != nullptr && processes::n() > 1;
    const dealii::IndexSet own           = own_rows_only ? processes::owned_rows(matrix->m()) : dealii::IndexSet();
    std::vector<GlobalDof> dofs(dim);
    for (auto &c : contributions)
      {
        std::copy(c.dofs.begin(), c.dofs.end(), dofs.begin());
        c.residual *= -1.;
        if (own_rows_only)
          {
            // The residual on every process alike (the same bits), apart
            // from the matrix (the joint call may add in another order).
            update_constraints.distribute_local_to_global(c.residual, dofs, minus_residual);
            if (own.is_element(dofs[0]))
              update_constraints.distribute_local_to_global(c.tangent, dofs, *matrix);
          }
        else if (matrix != nullptr)
          update_constraints.distribute_local_to_global(c.tangent, c.residual, dofs, *matrix, minus_residual);
        else
          update_constraints.distribute_local_to_global(c.residual, dofs, minus_residual);
      }
    assembly_counts.contact_assemblies += info.contact ? 1 : 0;
    assembly_counts.friction_terms += info.friction_terms;
    return info;
  }



  template <int dim>
  double
  SystemAssembler<dim>::relative_residual(const Vector<double> &minus_residual) const
  {
    // The reactions: the raw residual at dofs the constraints hold.
    double reaction_squared = 0;
    for (unsigned int i = 0; i < raw.size(); ++i)
      if (update_constraints.is_constrained(i))
        reaction_squared += raw[i] * raw[i];
    const double residual = minus_residual.l2_norm();
    if (residual == 0)
      return 0;
    return residual / std::max(std::sqrt(reaction_squared), 1e-300);
  }



  template <int dim>
  double
  SystemAssembler<dim>::roundoff_bound(const SparseMatrix<double> &matrix,
                                       const Vector<double> &      v,
                                       const MixedPenalty<dim> *   mixed) const
  {
    // The formula of residual_floor() was measured for Newtonian flow; a
    // strongly shear-thinning law puts its plateau higher (doc/benchmarks.md,
    // "Figures behind the code's rules").
    // On P processes each sums its block of rows (processes::owned_rows()),
    // the two sums then summed over the processes: the same bits on every
    // process, at a P-th of the work.
    std::vector<double>    squares(2, 0.); // free rows, reactions
    const Vector<double>   penalty_rows = mixed != nullptr ? mixed->penalty_magnitude(v) : Vector<double>();
    const dealii::IndexSet rows         = processes::owned_rows(matrix.m());
    for (const auto i : rows)
      if (update_constraints.is_constrained(i))
        squares[1] += raw[i] * raw[i];
      else
        {
          double row = mixed != nullptr ? penalty_rows[i] : 0.;
          for (auto entry = matrix.begin(i); entry != matrix.end(i); ++entry)
            row += std::abs(entry->value() * v[entry->column()]);
          squares[0] += row * row;
        }
    processes::sum(squares);
    if (squares[1] == 0)
      return 0;
    return std::min(std::numeric_limits<double>::epsilon() * std::sqrt(squares[0] / squares[1]), 1e-4);
  }



  template <int dim>
  Vector<double>
  SystemAssembler<dim>::nodal_flow_residual(const Vector<double> &           v,
                                            const FlowTerms<dim> &           terms,
                                            const AffineConstraints<double> &hanging_node_constraints) const
  {
    Vector<double> unused, reactions;
    flow.assemble_residual(dof_handler, v, terms, update_constraints, unused, reactions);
    hanging_node_constraints.condense(reactions);
    return reactions;
  }

  template class SystemAssembler<2>;
  template class SystemAssembler<3>;
} // namespace dieflow
