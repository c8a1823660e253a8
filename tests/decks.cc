// Every steady deck shipped in parameters/ runs and keeps its laws
// (tests/decks.h says which and why; the decks in time: decks_in_time.cc).
#include "decks.h"

int
main()
{
  check_decks(false);
}
