#!/usr/bin/env bash
# brdfbake quick start on Debian 12: installs what is missing, builds, then
#   demo  builds the tool, the libraries and the Python module (no tests, no benchmarks), bakes the
#         sample maps of data_samples/specs/phong_eye.json into out/, then does it again from Python
#         (the brdfbake module, docs/python.md)
#   test  checks the sources' formatting (scripts/check_format.sh), installs the test-only npm packages
#         of tests/js when npm is there, then runs the whole test suite twice (what CI runs): a shared
#         Release build, then a static build with clang's AddressSanitizer and
#         UndefinedBehaviorSanitizer (no benchmarks; its consumer_* tests check the static package,
#         so the Release pass skips its static rebuild). Each stage prints how long it took.
# Usage: scripts/quickstart.sh demo|test
set -euo pipefail
mode="${1:-}"
case "$mode" in demo|test) ;; *) echo "usage: $0 demo|test" >&2; exit 2 ;; esac
cd "$(dirname "$0")/.."

packages=(build-essential cmake libeigen3-dev libceres-dev libopenimageio-dev nlohmann-json3-dev
          libgtest-dev libtbb-dev libcli11-dev libbenchmark-dev librapidcheck-dev libmatio-dev zlib1g-dev gnuplot-nox
          python3-dev pybind11-dev python3-numpy python3-pytest)  # the last four: the Python module and its tests
# The test run also checks the formatting of the sources.
# The test run also checks the formatting of the sources and builds the sanitizer pass with clang
# (faster to compile than GCC under the sanitizers: 23 s against 39 s for tests/env/test_prefilter.cpp).
[ "$mode" = test ] && packages+=(clang-format git clang-14 libclang-rt-14-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "Installing: ${missing[*]}"
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

jobs="$(nproc)"
stage() {  # stage MESSAGE: prints it with the seconds since the script started (CI times its stages)
  echo "== $1 ($SECONDS s since the start)"
}
with_tests=ON; [ "$mode" = demo ] && with_tests=OFF
# The sanitizer pass below is static and checks the static package: no static rebuild here.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DBUILD_SHARED_LIBS=ON -DBRDFBAKE_BUILD_TESTS=$with_tests \
      -DBRDFBAKE_BUILD_BENCH=$with_tests -DBRDFBAKE_TEST_OTHER_LINKAGE=OFF
cmake --build build -j "$jobs"
stage "Release build done"

if [ "$mode" = demo ]; then
  build/cli/brdfbake bake data_samples/specs/phong_eye.json --out-dir out
  build/cli/brdfbake info out/phong_eye.exr
  echo "Baked maps are in out/ (OpenEXR, float RGBA). Try: build/cli/brdfbake sample out/phong_eye.exr --dir 0,0.3,1"
  # The Python module, built for the interpreter CMake chose (one that imports numpy: Debian's /usr/bin/python3
  # when the python3 first on PATH has no numpy).
  python="$(sed -n 's/^Python3_EXECUTABLE:FILEPATH=//p' build/CMakeCache.txt)"
  if [ -d build/python/brdfbake ] && [ -n "$python" ]; then
    PYTHONPATH=build/python "$python" -c 'import brdfbake; m = brdfbake.bake("data_samples/specs/phong_eye.json", out_dir="out").maps[0]; print("from Python:", m.output, brdfbake.read_map(m.output).sample([0, 0.3, 1]))'
    echo "Python: PYTHONPATH=$PWD/build/python $python (docs/python.md)"
  else
    echo "The Python module was not built (see the configure output above)"
  fi
else
  scripts/check_format.sh
  # Test-only readers for the texture containers (tests/js: ktx-parse, parse-dds). The tests that use
  # them skip with a message when node or the packages are missing.
  if command -v npm >/dev/null 2>&1 && npm view ktx-parse version >/dev/null 2>&1; then
    (cd tests/js && npm ci --no-audit --no-fund --silent) || echo "npm ci in tests/js failed: the independent KTX2/DDS reader tests will skip"
  else
    echo "npm or its registry is not reachable: the independent KTX2/DDS reader tests will skip"
  fi
  ctest --test-dir build --output-on-failure -j "$jobs"
  stage "Release tests passed; the same suite under AddressSanitizer and UndefinedBehaviorSanitizer"
  CC=clang-14 CXX=clang++-14 cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=Sanitize \
        -DCMAKE_CXX_FLAGS_SANITIZE="-O1 -g1" -DBRDFBAKE_SANITIZE=address,undefined -DBRDFBAKE_BUILD_BENCH=OFF \
        -DBRDFBAKE_TEST_OTHER_LINKAGE=OFF
  cmake --build build-sanitize -j "$jobs"
  stage "Sanitizer build done"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build-sanitize --output-on-failure -j "$jobs"
  stage "Sanitizer tests passed"
fi
