// Every deck in time (Problem = incremental) shipped in parameters/ runs
// and keeps, at its last step, the laws of tests/decks.h.
#include "decks.h"

int
main()
{
  check_decks(true);
}
