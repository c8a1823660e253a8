// The steady decks shipped in parameters/ that sort before die2d-s (die2d's
// N0, N1p, N3, P1, held land, hot, and the default deck) run and keep their
// laws (tests/decks.h says which and why; the others: decks_middle.cc and
// decks_rest.cc; the decks in time: decks_in_time.cc).
#include "decks.h"

int
main()
{
  check_decks(false, "", "die2d-s");
}
