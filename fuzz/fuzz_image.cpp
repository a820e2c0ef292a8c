// libFuzzer target: image input: readImage on OpenEXR, Radiance HDR, PNG and TIFF (their headers checked by
// image_header.cpp first; extension from the magic, else the first byte). See fuzz/README.md.
#include "fuzz_targets.hpp"

BRDFBAKE_FUZZ_TARGET("image")
