// libFuzzer target: Cornell ASTM E1392 text tables: readAstm. See fuzz/README.md.
#include "fuzz_targets.hpp"

BRDFBAKE_FUZZ_TARGET("astm")
