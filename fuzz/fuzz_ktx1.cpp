// libFuzzer target: KTX 1.1 (readTexture, then readImage) on a .ktx file. See fuzz/README.md.
#include "fuzz_targets.hpp"

BRDFBAKE_FUZZ_TARGET("ktx1")
