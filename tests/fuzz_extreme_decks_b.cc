// Fuzz corpus, part 2 (fuzz_extreme.h): 80 extreme die2d decks from seed 2; 44 converged on 2026-12-01 (AMD EPYC), the bound two below (another BLAS's round-off may tip a deck at the edge).
#include "fuzz_extreme.h"

int
main()
{
  fuzz::run_extreme_corpus(2, 80, 42);
}
