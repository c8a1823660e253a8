// The steady decks shipped in parameters/ from die2d-s to roundbar (die2d
// Sellars-Tegart, the slab, pop2008, rectbar3d) run and keep their laws
// (tests/decks.h says which and why).
#include "decks.h"

int
main()
{
  check_decks(false, "die2d-s", "roundbar");
}
