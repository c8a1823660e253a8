// What a nonlinear iteration asks of a discrete system: which Jacobian, and how many state changes.
#ifndef dieflow_linearization_h
#define dieflow_linearization_h

namespace dieflow
{
  /// Which Jacobian to assemble.
  enum class Linearization
  {
    /// eta frozen at the current iterate: successive substitution (the paper's sequence (7)).
    picard,
    /// the consistent tangent, including d eta / d epsdot.
    newton
  };

  /// How many contact directions changed state in an update.
  struct StateChanges
  {
    /// Directions that entered or left contact (the active set).
    unsigned int normal = 0;
    /// Stick <-> slip, or a new slip direction.
    unsigned int tangential = 0;

    unsigned int
    total() const
    {
      return normal + tangential;
    }
  };
} // namespace dieflow

#endif
