// Fuzz corpus, part 2 (fuzz_extreme.h): the last 40 of 80 extreme die2d decks from seed 1 (the others: fuzz_extreme_decks_a); on 2026-12-05 (AMD EPYC; a failed Newton iteration solved again at Coulomb's fixed point and by friction continuation, penalty factors above 1e10 solved at 1e10, lambda at most 1e10 x the viscosity at the start flow's RMS strain rate) 36 converged (the frozen bounds coupled to F_n again once the states settle), and of the 4 that exit 2, none converged with its advice followed; the bounds two below, one for the advice (another BLAS's round-off may tip a deck at the edge; a bound of 0 holds nothing).
#include "fuzz_extreme.h"

int
main()
{
  fuzz::run_extreme_corpus(1, 80, 34, 0, 40);
}
