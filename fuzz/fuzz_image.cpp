// libFuzzer target: image input: readImage on .hdr or .exr (extension from the magic, else the first byte). See
// fuzz/README.md.
#include "fuzz_targets.hpp"

BRDFBAKE_FUZZ_TARGET("image")
