// libFuzzer target: DDS (readTexture, then readImage) on a .dds file. See fuzz/README.md.
#include "fuzz_targets.hpp"

BRDFBAKE_FUZZ_TARGET("dds")
