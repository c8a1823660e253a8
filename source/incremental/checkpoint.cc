// The deck's checkpoint entries of a run in time: how often, and where to go on from.
#include <dieflow/incremental/checkpoint.h>

#include <filesystem>

namespace dieflow
{
  void
  CheckpointParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Checkpoint interval",
                      "10",
                      dealii::Patterns::Integer(0),
                      "Write the state of the run to Output directory/checkpoint.dat "
                      "(replacing the last one) every this many steps, at the last step, "
                      "and when SIGINT or SIGTERM stops the run between steps; 0: only "
                      "at the last step and when stopped. Restart from goes on from it.");
    prm.declare_entry("Restart from",
                      "",
                      dealii::Patterns::Anything(),
                      "A checkpoint.dat of an earlier run of this deck (relative to the "
                      "deck's folder): the run goes on from its step to End time, to the "
                      "same result as a run that was not stopped. The deck must give the "
                      "same Time step (End time may be later). Empty: start at t = 0.");
  }



  void
  CheckpointParameters::parse_parameters(ParameterHandler &prm, const std::string &deck_directory)
  {
    interval     = prm.get_integer("Checkpoint interval");
    restart_from = prm.get("Restart from");
    if (!restart_from.empty() && std::filesystem::path(restart_from).is_relative() && !deck_directory.empty())
      restart_from = (std::filesystem::path(deck_directory) / restart_from).string();
  }
} // namespace dieflow
