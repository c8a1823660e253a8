// Fuzz corpus, part 2 (fuzz_extreme.h): the first 40 of 80 extreme die2d decks from seed 1 (the others: fuzz_extreme_decks_e); on 2026-12-04 (AMD EPYC; a failed Newton iteration solved again at Coulomb's fixed point and by friction continuation, penalty factors above 1e10 solved at 1e10) 35 converged, and of the 5 that exit 2, 0 converged with their advice followed; the bounds two below, one for the advice (another BLAS's round-off may tip a deck at the edge; a bound of 0 holds nothing).
#include "fuzz_extreme.h"

int
main()
{
  fuzz::run_extreme_corpus(1, 40, 36, 0);
}
