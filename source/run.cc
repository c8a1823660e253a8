#include <dieflow/problem.h>
#include <dieflow/run.h>

#include <filesystem>
#include <fstream>
#include <iostream>

namespace dieflow
{
  namespace
  {
    void
    declare_deck(ParameterHandler &prm, const DeckLayout &layout)
    {
      // Entries do not depend on the dimension but for the number of
      // components of expressions; 3D reuses the 2D declarations' names.
      if (layout.dimension == 2)
        DieFlowProblem<2>::declare_parameters(prm, layout);
      else
        throw InputError("Dimension: 3 is not available in this version of dieflow; use 2");
    }
  } // namespace



  void
  read_deck(const std::string &                            file_name,
            ParameterHandler &                             prm,
            const std::function<void(ParameterHandler &)> &extra)
  {
    require(static_cast<bool>(std::ifstream(file_name)),
            "deck",
            "cannot open '" + file_name + "' (missing or unreadable)");
    DeckLayout layout;
    {
      ParameterHandler first;
      DieFlowProblem<2>::declare_parameters(first, layout);
      if (extra)
        extra(first);
      first.parse_input(file_name, "", /*skip_undefined=*/true);
      layout.dimension    = first.get_integer("Dimension");
      layout.velocity_ids = BoundaryConditions<2>::read_velocity_ids(first);
    }
    declare_deck(prm, layout);
    if (extra)
      extra(prm);
    prm.parse_input(file_name);
  }



  void
  declare_default_deck(ParameterHandler &prm)
  {
    declare_deck(prm, DeckLayout());
  }



  RunSummary
  run_deck(ParameterHandler &prm, const std::string &deck_directory, std::ostream &log)
  {
    DieFlowProblem<2> problem(prm, deck_directory, log);
    return problem.run();
  }



  std::string
  deck_error_message(const std::exception &exc, const std::string &file_name)
  {
    // deal.II names the deck by the path it was given; the file's name says
    // the same to the user, wherever the deck lives.
    std::string message = one_line_message(exc);
    const std::string name = std::filesystem::path(file_name).filename().string();
    for (std::size_t at; !file_name.empty() && (at = message.find(file_name)) != std::string::npos;)
      message.replace(at, file_name.size(), name);
    return message;
  }



  int
  run_command_line(int argc, char **argv)
  {
    const std::string usage =
      "usage: dieflow DECK.prm          run a deck (results in its Output directory)\n"
      "       dieflow --print-parameters print the default deck with every entry documented\n"
      "       dieflow --help             this text\n"
      "exit status: 0 converged, 1 bad input, 2 not converged (summary.json is still written)\n";
    if (argc != 2)
      {
        std::cerr << usage;
        return exit_bad_input;
      }
    const std::string argument = argv[1];
    if (argument == "--help" || argument == "-h")
      {
        std::cout << usage;
        return exit_converged;
      }
    try
      {
        if (argument == "--print-parameters")
          {
            ParameterHandler prm;
            declare_default_deck(prm);
            prm.print_parameters(std::cout, ParameterHandler::PRM);
            return exit_converged;
          }
        require(argument.empty() || argument[0] != '-', "command line", "unknown option '" + argument + "'\n" + usage);

        ParameterHandler prm;
        read_deck(argument, prm);
        std::cout << "dieflow: " << argument << std::endl;
        const RunSummary summary =
          run_deck(prm, std::filesystem::path(argument).parent_path().string(), std::cout);
        std::cout << (summary.converged ? "converged" : "NOT converged: " + summary.failure) << "; results in "
                  << prm.get("Output directory") << "/ (summary.json"
                  << (prm.get_bool("Write VTU") ? ", solution.pvd)" : ")") << ", wall time "
                  << summary.wall_time << " s" << std::endl;
        return summary.converged ? exit_converged : exit_not_converged;
      }
    catch (const InputError &error)
      {
        std::cerr << "dieflow: error: " << error.what() << std::endl;
        return exit_bad_input;
      }
    catch (const dealii::ExceptionBase &exc)
      {
        // ParameterHandler reports unknown entries, bad values and syntax
        // errors of the deck through deal.II exceptions.
        std::cerr << "dieflow: error: " << deck_error_message(exc, argument) << std::endl;
        return exit_bad_input;
      }
    catch (const std::exception &exc)
      {
        std::cerr << "dieflow: internal error: " << one_line_message(exc) << std::endl;
        return exit_internal;
      }
  }
} // namespace dieflow
