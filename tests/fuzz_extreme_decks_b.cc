// Fuzz corpus, part 2 (fuzz_extreme.h): 80 extreme die2d decks from seed 2; on 2026-12-05 (AMD EPYC; a failed Newton iteration solved again at Coulomb's fixed point and by friction continuation, penalty factors above 1e10 solved at 1e10, lambda at most 1e10 x the viscosity at the start flow's RMS strain rate) 78 converged (Coulomb's fixed point given eight times Newton's iterations, 2026-12-06), and of the 2 that exit 2, 1 converged with its advice followed; the bounds two below, one for the advice (another BLAS's round-off may tip a deck at the edge; a bound of 0 holds nothing).
#include "fuzz_extreme.h"

int
main()
{
  fuzz::run_extreme_corpus(2, 80, 76, 0);
}
