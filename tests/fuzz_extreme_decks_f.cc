// Fuzz corpus, part 2 (fuzz_extreme.h): decks 20 to 39 of 80 extreme die2d decks from seed 3 (the others: fuzz_extreme_decks_c, _d); on 2026-12-05 (AMD EPYC; a failed Newton iteration solved again at Coulomb's fixed point and by friction continuation, penalty factors above 1e10 solved at 1e10, lambda at most 1e10 x the viscosity at the start flow's RMS strain rate) 18 converged (a failed stage of the continuation in m goes on from the last converged stage's pressure too), and of the 2 that exit 2, none converged with its advice followed; the bounds two below, one for the advice (another BLAS's round-off may tip a deck at the edge; a bound of 0 holds nothing).
#include "fuzz_extreme.h"

int
main()
{
  fuzz::run_extreme_corpus(3, 40, 16, 0, 20);
}
