// Fuzz corpus, part 2 (fuzz_extreme.h): the first 40 of 80 extreme die2d decks from seed 3 (the others: fuzz_extreme_decks_d); on 2026-12-04 (AMD EPYC; a penalty that loses the flow turned augmented) 22 converged, and of the 18 that exit 2, 7 converged with their advice followed; the bounds two below (another BLAS's round-off may tip a deck at the edge).
#include "fuzz_extreme.h"

int
main()
{
  fuzz::run_extreme_corpus(3, 40, 20, 5);
}
