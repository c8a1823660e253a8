// The steady decks shipped in parameters/ from roundbar on (the round bars,
// upsetting, wire drawing) run and keep their laws (tests/decks.h says which
// and why; those before: decks.cc, decks_middle.cc).
#include "decks.h"

int
main()
{
  check_decks(false, "roundbar");
}
