// libFuzzer target: KTX2 (readTexture, then readImage) on a .ktx2 file. See fuzz/README.md.
#include "fuzz_targets.hpp"

BRDFBAKE_FUZZ_TARGET("ktx2")
