// Fuzz corpus, part 2 (fuzz_extreme.h): 80 extreme die2d decks from seed 3.
#include "fuzz_extreme.h"

int
main()
{
  fuzz::run_extreme_corpus(3, 80);
}
