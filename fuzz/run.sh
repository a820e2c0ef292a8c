#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, build-fuzz/) if needed, assembles their corpora and runs each
# target in turn, one worker, under nice -n 19. See fuzz/README.md.
#
#   fuzz/run.sh [SECONDS_PER_TARGET] [TARGET...]     default: 600 s, every target
#
# Seeds: fuzz/corpus/<target>/ (committed, tiny), data_samples/ and, when present, the real measured
# tables in ../shared/data/ (copied into the scratch corpus, never into the repository).
# Corpora grow in build-fuzz/corpus/<target>/ across runs; findings (crash-*, leak-*, timeout-*,
# oom-*) are kept in build-fuzz/artifacts/<target>/ and logs in build-fuzz/logs/<target>.log.
# By default each target runs its whole time in libFuzzer's fork mode with one worker, going on
# after crashes, leaks, timeouts and OOMs (each saved as an artifact), so one shallow finding does not
# end the run; FUZZ_MODE=single stops at the first finding as plain libFuzzer does.
# Prints one summary line per target (new findings are replayed and grouped by what and where);
# exits 1 if any target found something.
# Environment: CC/CXX (default clang-14/clang++-14), BRDFBAKE_FUZZ_JOBS (build jobs, default 1),
# BRDFBAKE_SHARED_DIR (default ../shared beside the repository), FUZZ_MODE (fork | single),
# FUZZ_EXTRA_ARGS (more libFuzzer flags).
set -uo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build-fuzz"
all_targets=(spec fit astm pbrt merl mat image ktx2 ktx1 dds)

seconds="${1:-600}"
if ! [[ "$seconds" =~ ^[0-9]+$ ]]; then
  echo "usage: $0 [SECONDS_PER_TARGET] [TARGET...]   targets: ${all_targets[*]}" >&2
  exit 2
fi
[ $# -gt 0 ] && shift
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=("${all_targets[@]}")
for t in "${targets[@]}"; do
  [[ " ${all_targets[*]} " == *" $t "* ]] || { echo "unknown target '$t' (known: ${all_targets[*]})" >&2; exit 2; }
done

max_len_for() {
  case "$1" in
    spec|fit) echo 8192 ;;
    astm|pbrt) echo 32768 ;;
    merl|mat) echo 4096 ;;
    image) echo 65536 ;;
    ktx2|ktx1|dds) echo 16384 ;;
  esac
}

# ---- build ---------------------------------------------------------------------------------------
if [ ! -f "$build/CMakeCache.txt" ]; then
  CC="${CC:-clang-14}" CXX="${CXX:-clang++-14}" nice -n 19 cmake -S "$root" -B "$build" \
    -DBRDFBAKE_BUILD_FUZZERS=ON -DBRDFBAKE_BUILD_TESTS=OFF -DBRDFBAKE_BUILD_BENCH=OFF \
    -DBRDFBAKE_BUILD_CLI=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null || { echo "configure failed" >&2; exit 2; }
fi
build_targets=()
for t in "${targets[@]}"; do build_targets+=(--target "fuzz_$t"); done
nice -n 19 cmake --build "$build" -j "${BRDFBAKE_FUZZ_JOBS:-1}" "${build_targets[@]}" >"$build/fuzz-build.log" 2>&1 ||
  { tail -30 "$build/fuzz-build.log" >&2; echo "build failed (log: $build/fuzz-build.log)" >&2; exit 2; }

# ---- corpora -------------------------------------------------------------------------------------
shared="${BRDFBAKE_SHARED_DIR:-$root/../shared}"
seeds="$build/seeds"
rm -rf "$seeds"
copy_seeds() {  # copy_seeds TARGET FILE...
  local target="$1"; shift
  mkdir -p "$seeds/$target"
  for f in "$@"; do [ -f "$f" ] && cp "$f" "$seeds/$target/"; done
}
shared_note=""
for t in "${targets[@]}"; do
  mkdir -p "$seeds/$t" "$build/corpus/$t" "$build/artifacts/$t" "$build/logs"
  [ -d "$root/fuzz/corpus/$t" ] && cp "$root/fuzz/corpus/$t"/* "$seeds/$t/" 2>/dev/null
  case "$t" in
    spec) copy_seeds spec "$root"/data_samples/specs/*.json ;;
    fit) copy_seeds fit "$root"/data_samples/fits/*.json ;;
    astm) copy_seeds astm "$root"/data_samples/tables/*.astm ;;
    image) copy_seeds image "$root"/data_samples/environments/*.exr ;;
  esac
  case "$t" in
    astm|pbrt)
      if [ -d "$shared/data/cornell" ]; then
        if [ "$t" = astm ]; then copy_seeds astm "$shared"/data/cornell/*.astm; else copy_seeds pbrt "$shared"/data/cornell/*.brdf; fi
      else
        shared_note="shared data not found at $shared/data/cornell: skipping the real measured seeds"
      fi ;;
  esac
done
[ -n "$shared_note" ] && echo "$shared_note"

# The first line of a log that says what went wrong: an uncaught exception and its what(), a
# sanitizer's SUMMARY, a UBSan runtime error, or libFuzzer's own verdict (timeout, out-of-memory, ...).
describe_finding() {
  local log="$1" exc
  exc="$(grep -m1 -oE "terminate called after throwing an instance of '[^']*'" "$log")"
  if [ -n "$exc" ]; then
    echo "uncaught ${exc#terminate called after throwing an instance of }: $(grep -m1 -oE 'what\(\): +.{0,120}' "$log" | sed 's/what(): *//')"
    return
  fi
  grep -m1 -oE 'runtime error: .{0,140}' "$log" && return
  grep -m1 -oE 'SUMMARY: (AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer): .{0,140}' "$log" && return
  grep -m1 -oE 'ERROR: libFuzzer: .{0,140}' "$log"
}

# Where a finding happened: the first stack frame outside libFuzzer, the sanitizers, the allocator
# and the C/C++ runtime ("function" or "library+offset"), and the first brdfbake frame.
where_finding() {
  local log="$1" frames first ours
  frames="$(grep -E '^ +#[0-9]+ 0x' "$log" | grep -vE 'fuzzer::|__sanitizer|__asan|__lsan|__ubsan|__interceptor|in (malloc|calloc|realloc|free|operator new|operator delete|abort|raise)\b|libc\.so|libstdc\+\+|__cxa_|LLVMFuzzer|brdfbake::fuzzing|in main ')"
  first="$(echo "$frames" | head -1 | sed -E 's/^ +#[0-9]+ 0x[0-9a-f]+ +(in )?//; s/ \(BuildId.*//; s/\(.*\/([^/]+\+0x[0-9a-f]+)\)/\1/; s/ \/work\/[^ ]*\/([^/ ]+:[0-9]+)(:[0-9]+)?$/ \1/' | cut -c1-110)"
  ours="$(echo "$frames" | grep -m1 -oE 'brdfbake::[A-Za-z_:]+\(?' | tr -d '(')"
  echo "${first}${ours:+ (via $ours)}"
}

# Replays one artifact in a fresh process and says what and where.
replay_finding() {
  local bin="$1" artifact="$2" log
  log="$(mktemp)"
  timeout 120 nice -n 19 "$bin" -rss_limit_mb=2048 -timeout=10 "$artifact" >"$log" 2>&1
  local what where
  what="$(describe_finding "$log" | sed -E 's/^ERROR: libFuzzer: //; s/\(used: [0-9]+Mb; limit: [0-9]+Mb\)/(rss over the limit)/; s/malloc\([0-9]+\)/malloc(huge)/')"
  [ -z "$what" ] && what="does not reproduce alone"
  where="$(where_finding "$log")"
  rm -f "$log"
  echo "${what}${where:+ at $where}"
}

# ---- run -----------------------------------------------------------------------------------------
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:symbolize=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
found_any=0
summary=()
for t in "${targets[@]}"; do
  artifacts="$build/artifacts/$t"
  log="$build/logs/$t.log"
  before="$(ls "$artifacts" 2>/dev/null | sort)"
  dict=()
  case "$t" in spec|fit) dict=(-dict="$root/fuzz/json.dict") ;; esac
  mode=()
  [ "${FUZZ_MODE:-fork}" = fork ] && mode=(-fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1)
  start=$(date +%s)
  # shellcheck disable=SC2086
  nice -n 19 "$build/fuzz/fuzz_$t" "$build/corpus/$t" "$seeds/$t" \
    -max_total_time="$seconds" -rss_limit_mb=2048 -max_len="$(max_len_for "$t")" -timeout=10 \
    -artifact_prefix="$artifacts/" -print_final_stats=1 "${mode[@]}" "${dict[@]}" ${FUZZ_EXTRA_ARGS:-} >"$log" 2>&1
  rc=$?
  wall=$(( $(date +%s) - start ))
  # Scratch folders of fuzzing processes that died without their exit handler (crashes, OOMs).
  for d in /dev/shm/brdfbake-fuzz-* "${TMPDIR:-/tmp}"/brdfbake-fuzz-*; do
    [ -d "$d" ] && ! kill -0 "${d##*-}" 2>/dev/null && rm -rf "$d"
  done
  after="$(ls "$artifacts" 2>/dev/null | sort)"
  new="$(comm -13 <(echo "$before") <(echo "$after") | grep -E '^(crash|leak|timeout|oom|slow-unit)-' | tr '\n' ' ')"
  runs="$(grep -oE 'stat::number_of_executed_units: [0-9]+' "$log" | tail -1 | awk '{print $2}')"
  [ -z "$runs" ] && runs="$(grep -oE '^#[0-9]+' "$log" | tail -1 | tr -d '#')"
  # in fork mode cov/ft count the merged corpus (not comparable with single-process numbers)
  cov="$(grep -oE 'cov: [0-9]+ ft: [0-9]+' "$log" | tail -1)"
  corpus_n="$(ls "$build/corpus/$t" | wc -l)"
  if [ -n "$new" ] || [ "$rc" -ne 0 ]; then
    found_any=1
    # shellcheck disable=SC2206
    new_files=($new)
    counts="$(printf '%s\n' "${new_files[@]}" | sed 's/-.*//' | sort | uniq -c | awk '{printf "%s%s %s", (NR>1?", ":""), $1, $2}')"
    if [ ${#new_files[@]} -eq 0 ]; then
      what="$(describe_finding "$log")"
      result="FOUND: ${what:-exit code $rc} (log: ${log#$root/})"
    else
      # Replay the newest few and group them by what and where.
      groups="$(for f in $(ls -t "${new_files[@]/#/$artifacts/}" | head -"${FUZZ_REPLAY:-8}"); do
                  echo "$(replay_finding "$build/fuzz/fuzz_$t" "$f")	$(basename "$f")"
                done | sort | awk -F'\t' '{n[$1]++; ex[$1]=$2} END {for (k in n) printf "  - %s [x%d, e.g. %s]\n", k, n[k], ex[k]}')"
      result="FOUND: ${counts} in ${artifacts#$root/}/"$'\n'"$groups"
    fi
  else
    result="nothing found"
  fi
  line="$(printf '%-6s %5ss  runs %-10s %-20s corpus %-5s %s' "$t" "$wall" "${runs:-?}" "${cov:-cov: ?}" "$corpus_n" "$result")"
  echo "$line"
  summary+=("$line")
done
echo "---- summary ----"
printf '%s\n' "${summary[@]}"
exit "$found_any"
