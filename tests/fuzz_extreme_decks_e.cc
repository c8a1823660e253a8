// Fuzz corpus, part 2 (fuzz_extreme.h): the last 40 of 80 extreme die2d decks from seed 1 (the others: fuzz_extreme_decks_a); on 2026-12-05 (AMD EPYC; a failed Newton iteration solved again at Coulomb's fixed point and by friction continuation, penalty factors above 1e10 solved at 1e10, lambda at most 1e10 x the viscosity at the start flow's RMS strain rate) 39 converged (the frozen bounds coupled to F_n again once the states settle; Coulomb's fixed point given eight times Newton's iterations, 2026-12-06), and the 1 that exits 2 did not converge with its advice followed; the bounds two below, one for the advice (another BLAS's round-off may tip a deck at the edge; a bound of 0 holds nothing).
#include "fuzz_extreme.h"

int
main()
{
  fuzz::run_extreme_corpus(1, 80, 37, 0, 40);
}
