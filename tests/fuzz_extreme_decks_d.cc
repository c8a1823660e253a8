// Fuzz corpus, part 2 (fuzz_extreme.h): the last 40 of 80 extreme die2d decks from seed 3 (the others: fuzz_extreme_decks_c); on 2026-12-04 (AMD EPYC; a penalty that loses the flow turned augmented) 32 converged, and of the 8 that exit 2, 4 converged with their advice followed; the bounds two below (another BLAS's round-off may tip a deck at the edge).
#include "fuzz_extreme.h"

int
main()
{
  fuzz::run_extreme_corpus(3, 80, 30, 2, 40);
}
