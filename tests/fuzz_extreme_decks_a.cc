// Fuzz corpus, part 2 (fuzz_extreme.h): 80 extreme die2d decks from seed 1; on 2026-12-04 (AMD EPYC; a penalty that loses the flow turned augmented) 63 converged, and of the 17 that exit 2, 7 converged with their advice followed; the bounds two below (another BLAS's round-off may tip a deck at the edge).
#include "fuzz_extreme.h"

int
main()
{
  fuzz::run_extreme_corpus(1, 80, 61, 5);
}
