// The default deck that `dieflow --print-parameters` prints is a valid deck:
// read back, it gives the same values, and every entry carries
// documentation (a comment line above each 'set').
#include <dieflow/problem/run.h>

#include <fstream>
#include <iostream>
#include <sstream>

using namespace dieflow;

int
main()
{
  ParameterHandler printed;
  declare_default_deck(printed);
  std::ostringstream text;
  printed.print_parameters(text, ParameterHandler::PRM);
  std::ofstream("default.prm") << text.str();

  ParameterHandler reread;
  read_deck("default.prm", reread);
  std::ostringstream again;
  reread.print_parameters(again, ParameterHandler::PRM);
  std::cout << "printed deck reads back to the same deck: " << (again.str() == text.str() ? "yes" : "NO")
            << std::endl;

  std::istringstream lines(text.str());
  std::string        line, previous;
  unsigned int       entries = 0, undocumented = 0;
  while (std::getline(lines, line))
    {
      const auto first = line.find_first_not_of(' ');
      if (first != std::string::npos && line.compare(first, 4, "set ") == 0)
        {
          ++entries;
          const auto p = previous.find_first_not_of(' ');
          if (p == std::string::npos || previous[p] != '#')
            ++undocumented;
        }
      previous = line;
    }
  std::cout << "every entry is documented: " << (undocumented == 0 && entries > 40 ? "yes" : "NO") << std::endl;
}
