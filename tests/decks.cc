// The steady decks shipped in parameters/ that sort before roundbar (die2d,
// pop2008, rectbar3d) run and keep their laws (tests/decks.h says which and
// why; the others: decks_rest.cc; the decks in time: decks_in_time.cc).
#include "decks.h"

int
main()
{
  check_decks(false, "roundbar");
}
