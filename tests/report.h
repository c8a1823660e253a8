// One verdict line of a unit test: the claim, then yes or NO.
#ifndef dieflow_tests_report_h
#define dieflow_tests_report_h

#include <iostream>
#include <string>

inline void
report(const std::string &claim, const bool holds)
{
  std::cout << claim << ": " << (holds ? "yes" : "NO") << std::endl;
}

#endif
