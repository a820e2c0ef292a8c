// libFuzzer target: MATLAB .mat tables: readMat (through libmatio). See fuzz/README.md.
#include "fuzz_targets.hpp"

BRDFBAKE_FUZZ_TARGET("mat")
