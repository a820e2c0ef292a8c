// libFuzzer target: MERL .binary: readMerl. See fuzz/README.md.
#include "fuzz_targets.hpp"

BRDFBAKE_FUZZ_TARGET("merl")
