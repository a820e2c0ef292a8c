// libFuzzer target: pbrt-v2 .brdf tables: readPbrt. See fuzz/README.md.
#include "fuzz_targets.hpp"

BRDFBAKE_FUZZ_TARGET("pbrt")
