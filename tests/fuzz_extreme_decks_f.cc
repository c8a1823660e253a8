// Fuzz corpus, part 2 (fuzz_extreme.h): decks 20 to 39 of 80 extreme die2d decks from seed 3 (the others: fuzz_extreme_decks_c, _d); on 2026-12-05 (AMD EPYC; a failed Newton iteration solved again at Coulomb's fixed point and by friction continuation, penalty factors above 1e10 solved at 1e10, lambda at most 1e10 x the viscosity at the start flow's RMS strain rate) 19 converged (a failed stage of the continuation in m goes on from the last converged stage's pressure too; Coulomb's fixed point given eight times Newton's iterations, 2026-12-06), and the 1 that exits 2 did not converge with its advice followed; the bounds two below, one for the advice (another BLAS's round-off may tip a deck at the edge; a bound of 0 holds nothing).
#include "fuzz_extreme.h"

int
main()
{
  fuzz::run_extreme_corpus(3, 40, 17, 0, 20);
}
