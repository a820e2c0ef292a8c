// libFuzzer target: fit.json: readFitFile. See fuzz/README.md.
#include "fuzz_targets.hpp"

BRDFBAKE_FUZZ_TARGET("fit")
