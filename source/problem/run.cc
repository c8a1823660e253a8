// The program's command line: reading and checking a deck, running it, the one-line error messages, and the exit statuses.
#include <dieflow/base/interrupt.h>
#include <dieflow/base/processes.h>
#include <dieflow/problem/problem.h>
#include <dieflow/problem/run.h>
#include <dieflow/base/threads.h>

#include <algorithm>
#include <cstdlib>
#include <iomanip>
#include <map>
#include <filesystem>
#include <numeric>
#include <sstream>
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
        DieFlowProblem<3>::declare_parameters(prm, layout);
    }
  } // namespace



  namespace
  {
    /// Edit distance of two names, case ignored.
    unsigned int
    distance(const std::string &a, const std::string &b)
    {
      std::vector<unsigned int> row(b.size() + 1);
      std::iota(row.begin(), row.end(), 0u);
      for (unsigned int i = 1; i <= a.size(); ++i)
        {
          unsigned int diagonal = row[0];
          row[0]                = i;
          for (unsigned int j = 1; j <= b.size(); ++j)
            {
              const unsigned int above = row[j];
              row[j] = std::min({row[j] + 1,
                                 row[j - 1] + 1,
                                 diagonal + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1)});
              diagonal = above;
            }
        }
      return row[b.size()];
    }

    /**
     * " (did you mean 'X' in subsection Y?)" for a deck entry or subsection
     * the deck misspelt, from the names that @p prm declares; "" when
     * nothing is close.
     */
    std::string
    suggestion(const dealii::ExceptionBase &exc, const ParameterHandler &prm)
    {
      const std::string text = one_line_message(exc);
      std::string       wrong;
      bool              subsection = false;
      if (const auto at = text.find("No entry with name <"); at != std::string::npos)
        wrong = text.substr(at + 20, text.find('>', at + 20) - at - 20);
      else if (const auto at = text.find("no such subsection to be entered: "); at != std::string::npos)
        {
          wrong      = text.substr(at + 34);
          subsection = true;
        }
      if (wrong.empty())
        return "";

      // The declared names, with the subsections they live in.
      std::ostringstream listing;
      prm.print_parameters(listing, ParameterHandler::ShortPRM);
      std::istringstream           lines(listing.str());
      std::vector<std::string>     path;
      std::string                  line, best, best_where;
      unsigned int                 best_distance = std::numeric_limits<unsigned int>::max();
      const auto                   consider      = [&](const std::string &name) {
        const unsigned int d = distance(wrong, name);
        if (d < best_distance)
          {
            best_distance = d;
            best          = name;
            best_where.clear();
            for (const auto &part : path)
              best_where += (best_where.empty() ? "" : "/") + part;
          }
      };
      while (std::getline(lines, line))
        {
          const auto first = line.find_first_not_of(' ');
          if (first == std::string::npos)
            continue;
          line = line.substr(first);
          if (line.rfind("subsection ", 0) == 0)
            {
              if (subsection)
                consider(line.substr(11));
              path.push_back(line.substr(11));
            }
          else if (line == "end" && !path.empty())
            path.pop_back();
          else if (line.rfind("set ", 0) == 0 && !subsection)
            consider(dealii::Utilities::trim(line.substr(4, line.find('=') - 4)));
        }
      if (best.empty() || best_distance > std::max<unsigned int>(2, wrong.size() / 3))
        return "";
      return " (did you mean '" + best + "'" + (best_where.empty() ? "" : " in subsection " + best_where) + "?)";
    }
  } // namespace



  namespace
  {
    /// Length of the UTF-8 sequence that starts with @p c (0: not a lead byte).
    unsigned int
    utf8_length(const unsigned char c)
    {
      return c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xe ? 3 : (c >> 3) == 0x1e ? 4 : 0;
    }
  } // namespace



  void
  check_deck_text(const std::string &file_name)
  {
    std::ifstream      in(file_name, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    const std::string text = bytes.str();

    // Text only: a control byte or broken UTF-8 means a binary or corrupted
    // file, which ParameterHandler would read in part or misreport.
    unsigned int line = 1;
    for (std::size_t i = 0; i < text.size();)
      {
        const unsigned char c = text[i];
        if (c == '\n')
          ++line;
        unsigned int length = utf8_length(c);
        for (unsigned int k = 1; k < length; ++k)
          if (i + k >= text.size() || (static_cast<unsigned char>(text[i + k]) >> 6) != 0x2)
            length = 0;
        if (length == 0 || (c < 0x20 && c != '\n' && c != '\r' && c != '\t') || c == 0x7f)
          {
            std::ostringstream byte;
            byte << "0x" << std::hex << std::setw(2) << std::setfill('0') << static_cast<unsigned int>(c);
            throw InputError("deck: line " + std::to_string(line) + " has the byte " + byte.str() +
                             ", which is not text (a binary or corrupted file?)");
          }
        i += length;
      }

    // An entry set twice: ParameterHandler keeps the last value silently,
    // which is almost always an edit that left the old line behind.
    std::istringstream                 lines(text);
    std::vector<std::string>           path;
    std::map<std::string, unsigned int> first_line;
    std::string                        physical, logical;
    unsigned int                       number = 0, start = 0;
    while (std::getline(lines, physical))
      {
        ++number;
        if (logical.empty())
          start = number;
        physical = physical.substr(0, physical.find('#'));
        const std::string trimmed = dealii::Utilities::trim(physical);
        if (!trimmed.empty() && trimmed.back() == '\\')
          {
            logical += trimmed.substr(0, trimmed.size() - 1) + ' ';
            continue;
          }
        logical += trimmed;
        const std::string statement = dealii::Utilities::trim(logical);
        logical.clear();
        if (statement.rfind("subsection ", 0) == 0)
          path.push_back(dealii::Utilities::trim(statement.substr(11)));
        else if (statement == "end" && !path.empty())
          path.pop_back();
        else if (statement.rfind("set ", 0) == 0 && statement.find('=') != std::string::npos)
          {
            std::string name;
            for (const auto &part : path)
              name += part + "/";
            name += dealii::Utilities::trim(statement.substr(4, statement.find('=') - 4));
            const auto [at, inserted] = first_line.emplace(name, start);
            if (!inserted)
              throw InputError("deck: line " + std::to_string(start) + " sets " + name +
                               " a second time (first on line " + std::to_string(at->second) +
                               "); delete one of the two");
          }
      }
  }



  void
  read_deck(const std::string &                            file_name,
            ParameterHandler &                             prm,
            const std::function<void(ParameterHandler &)> &extra)
  {
    require(static_cast<bool>(std::ifstream(file_name)),
            "deck",
            "cannot open '" + file_name + "' (missing or unreadable)");
    check_deck_text(file_name);
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
    try
      {
        prm.parse_input(file_name);
      }
    catch (const dealii::ExceptionBase &exc)
      {
        throw InputError(deck_error_message(exc, file_name) + suggestion(exc, prm));
      }
  }



  void
  declare_default_deck(ParameterHandler &prm)
  {
    declare_deck(prm, DeckLayout());
  }



  RunSummary
  run_deck(ParameterHandler &prm, const std::string &deck_directory, std::ostream &log)
  {
    if (prm.get_integer("Dimension") == 3)
      {
        DieFlowProblem<3> problem(prm, deck_directory, log);
        return problem.run();
      }
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
    if (!file_name.empty() && name != file_name)
      for (std::size_t at = message.find(file_name); at != std::string::npos;
           at = message.find(file_name, at + name.size()))
        message.replace(at, file_name.size(), name);
    // deal.II 9.4 leaves the bracket open in its unknown-subsection message.
    const std::string open = "of file <" + name + ":";
    if (const auto at = message.find(open); at != std::string::npos)
      message.insert(at + open.size() - 1, ">");
    return message;
  }






  namespace
  {
    /// The exit of a run that failed with @p message: one line, from the
    /// first process where every process failed, else from this one,
    /// which then ends the others (processes::failed_together()).
    int
    end_with(const std::string &kind, const std::string &message, const int code)
    {
      if (processes::failed_together())
        {
          if (processes::writes_output())
            std::cerr << "dieflow: " << kind << ": " << message << std::endl;
          return code;
        }
      std::cerr << "dieflow: " << kind << ": " << message << " (MPI process " << processes::rank()
                << " alone; it ends the others)" << std::endl;
      MPI_Abort(processes::communicator(), code);
      return code;
    }
  } // namespace



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
    // Under mpirun -np P the processes run the deck together
    // (processes.h); the first writes the files and the screen lines.
    const processes::Session session;
    if (!session.launch_error().empty())
      {
        // Every process believes it is the first: the launcher's rank says which one reports.
        if (processes::launched().second == 0)
          std::cerr << "dieflow: error: " << session.launch_error() << std::endl;
        return exit_bad_input;
      }
    const bool first = processes::writes_output();
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
        std::ostream &out = first ? std::cout : processes::null_stream();

        ParameterHandler prm;
        read_deck(argument, prm);
        out << "dieflow: " << argument;
        if (processes::n() > 1)
          out << " (" << processes::n() << " MPI processes, " << threads::requested() << " threads each)";
        out << std::endl;
        interrupt::install_handlers();
        threads::use(threads::requested());
        const RunSummary summary =
          run_deck(prm, std::filesystem::path(argument).parent_path().string(), out);
        const std::string results = prm.get("Output directory") + "/ (summary.json" +
                                    (prm.get_bool("Write VTU") ? ", solution.pvd)" : ")");
        if (summary.interrupted)
          out << "INTERRUPTED: " << summary.failure << "; the results so far are in " << results
                    << ", summary.json marked \"interrupted\": true. "
                    << (summary.checkpoint_file.empty() ?
                          std::string(summary.problem == "steady" ?
                                        "A steady run has no checkpoint: run the deck again to finish it" :
                                        "No step was checkpointed: run the deck again") :
                          "To go on from step " + std::to_string(summary.checkpoint_step) +
                            ": set Incremental/Restart from = " + summary.checkpoint_file +
                            " and run the deck again")
                    << std::endl;
        else
          out << (summary.converged ? "converged" : "NOT converged: " + summary.failure) << "; results in "
                    << results << ", wall time " << std::fixed << std::setprecision(2) << summary.wall_time << " s"
                    << std::defaultfloat << std::endl;
        return summary.converged ? exit_converged : exit_not_converged;
      }
    // An error every process raised (the deck's, read by all; one of the
    // replicated state) is said once, by the first. An error of one process
    // alone (a file it could not write, say: DataOut's, a .vtu piece), the
    // others waiting for it in a collective, would leave them waiting for
    // ever: that process says it and ends them all.
    catch (const InputError &error)
      {
        return end_with("error", error.what(), exit_bad_input);
      }
    catch (const dealii::ExceptionBase &exc)
      {
        // ParameterHandler reports unknown entries, bad values and syntax
        // errors of the deck through deal.II exceptions.
        return end_with("error", deck_error_message(exc, argument), exit_bad_input);
      }
    catch (const std::exception &exc)
      {
        return end_with("internal error", one_line_message(exc), exit_internal);
      }
  }
} // namespace dieflow
