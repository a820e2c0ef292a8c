// libFuzzer target: bake specs: loadBakeSpec (JSON text, then parseBakeSpec; parse only, never bakes). See
// fuzz/README.md.
#include "fuzz_targets.hpp"

BRDFBAKE_FUZZ_TARGET("spec")
