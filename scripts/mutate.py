#!/usr/bin/env python3
"""Mutation testing: applies one mutant at a time from tests/mutants.json, rebuilds, runs that part's tests.

Each mutant replaces one exact piece of text (which must occur exactly once in its file) by a plausible
mistake: a sign, a factor of pi, a texel-centre offset, a cube face swapped, a Fresnel exponent, a clamp
removed, an off-by-one in a reader's bound, a unit. The script rebuilds the mutant's CMake targets in the
build folder (incrementally), runs the mutant's GoogleTest executables, and calls the mutant
  killed        when a test fails (or times out),
  survived      when every test passes,
  build-failed  when the mutated source does not compile (reported apart, not counted as killed).
Mutants marked "equivalent" in the list (with the reason) are not run and not scored.
The original file is always written back (also on Ctrl-C or SIGTERM) and checked byte for byte; at the end
the touched targets are rebuilt once from the original sources, so the build folder matches the tree.

Usage (from the repository root, after configuring a build folder with the tests on):
  scripts/mutate.py --list                 # the mutants, one a line, with the part and the reason
  scripts/mutate.py                        # all of them in build/ (about 60 to 90 minutes on 2 cores)
  scripts/mutate.py --build build --only fresnel-schlick-exponent,cube-face-swap --timeout 600 --json out.json
A baseline run of the same tests on the unmutated tree comes first (--no-baseline skips it); a failing
baseline stops the run, as a mutant could not be judged against it. Builds and tests run under `nice`.
Exit status: 0 when every mutant ran, 1 when interrupted, 2 when a file could not be restored, 3 when
the score is below --min-score. .ci/mutation is the scheduled entry point (not part of .ci/run).
"""
import argparse
import json
import os
import pathlib
import signal
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
DEFAULT_LIST = ROOT / "tests" / "mutants.json"
REQUIRED = ("id", "file", "find", "replace", "why", "targets", "tests")


class Interrupted(Exception):
    """SIGTERM, turned into an exception so that the finally blocks restore the tree."""


def on_sigterm(signum, frame):
    raise Interrupted(f"signal {signum}")


def load_mutants(path):
    """Reads and checks the list: fields present, ids unique, each `find` exactly once in its file."""
    mutants = json.loads(path.read_text())["mutants"]
    seen = set()
    for m in mutants:
        missing = [k for k in REQUIRED if k not in m]
        if missing:
            sys.exit(f"mutant {m.get('id', '?')}: missing {', '.join(missing)}")
        if m["id"] in seen:
            sys.exit(f"mutant {m['id']}: id appears twice")
        seen.add(m["id"])
        if m["find"] == m["replace"]:
            sys.exit(f"mutant {m['id']}: replace equals find")
        text = (ROOT / m["file"]).read_text()
        count = text.count(m["find"])
        if count != 1:
            sys.exit(f"mutant {m['id']}: the text to find occurs {count} times in {m['file']} (must be exactly once):\n"
                     f"  {m['find']!r}")
    return mutants


def part_of(mutant):
    """The library part a mutant hits: its 'part' field, or the first folder of its file."""
    return mutant.get("part") or mutant["file"].split("/")[0]


def print_list(mutants):
    for m in mutants:
        tag = "  [equivalent: " + m["equivalent"] + "]" if m.get("equivalent") else ""
        print(f"{m['id']:<34} {part_of(m):<9} {m['file']}\n    {m['why']}{tag}")
    parts = {}
    for m in mutants:
        parts[part_of(m)] = parts.get(part_of(m), 0) + 1
    print(f"{len(mutants)} mutants: " + ", ".join(f"{k} {v}" for k, v in sorted(parts.items())))


def nice(command):
    return ["nice", "-n", "15"] + command


def build(build_dir, targets, log):
    """Incremental build of the given targets; True when it succeeds."""
    command = nice(["cmake", "--build", str(build_dir), "--target", *targets, "-j2"])
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    log.append(result.stdout[-4000:])
    return result.returncode == 0


def find_executable(build_dir, name):
    """The test executable `name` somewhere under the build folder (tests/<part>/<name>)."""
    hits = [p for p in (build_dir / "tests").glob(f"*/{name}") if p.is_file() and os.access(p, os.X_OK)]
    if not hits:
        raise FileNotFoundError(f"no test executable {name} under {build_dir}/tests")
    return hits[0]


def run_tests(build_dir, tests, timeout):
    """Runs each {exe, filter} entry; returns (all passed, short description of the first failure)."""
    for t in tests:
        exe = find_executable(build_dir, t["exe"])
        command = nice([str(exe), "--gtest_brief=1"])
        if t.get("filter"):
            command.append("--gtest_filter=" + t["filter"])
        try:
            result = subprocess.run(command, cwd=exe.parent, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                    text=True, errors="replace", timeout=timeout)
        except subprocess.TimeoutExpired:
            return False, f"{t['exe']}: timed out after {timeout} s"
        if result.returncode != 0:
            failed = [line.split("]", 1)[1].strip() for line in result.stdout.splitlines()
                      if line.startswith("[  FAILED  ]") and "," not in line and "listed below" not in line]
            return False, f"{t['exe']}: " + (", ".join(failed[:3]) or f"exit {result.returncode}")
    return True, ""


def apply_and_test(mutant, build_dir, timeout):
    """Mutates the file, builds, tests, and restores the original bytes whatever happens."""
    path = ROOT / mutant["file"]
    original = path.read_bytes()
    mutated = original.decode().replace(mutant["find"], mutant["replace"], 1).encode()
    log = []
    try:
        path.write_bytes(mutated)
        if not build(build_dir, mutant["targets"], log):
            return {"status": "build-failed", "detail": log[-1][-600:]}
        passed, detail = run_tests(build_dir, mutant["tests"], timeout)
        return {"status": "survived" if passed else "killed", "detail": detail}
    finally:
        # A new write (newer than the mutant's objects) so that make rebuilds them from the original.
        path.write_bytes(original)
        if path.read_bytes() != original:
            raise RuntimeError(f"{path}: could not restore the original bytes")


def baseline(mutants, build_dir, timeout):
    """Builds every target once and runs every test once on the unmutated tree."""
    targets = sorted({t for m in mutants for t in m["targets"]})
    log = []
    if not build(build_dir, targets, log):
        sys.exit("baseline build failed:\n" + log[-1])
    seen, tests = set(), []
    for m in mutants:
        for t in m["tests"]:
            key = (t["exe"], t.get("filter", ""))
            if key not in seen:
                seen.add(key)
                tests.append(t)
    passed, detail = run_tests(build_dir, tests, timeout)
    if not passed:
        sys.exit("baseline tests fail on the unmutated tree: " + detail)


def summary(results):
    """The score line and the survivors' reasons."""
    count = {s: sum(1 for r in results if r["status"] == s) for s in ("killed", "survived", "build-failed")}
    scored = count["killed"] + count["survived"]
    score = 100.0 * count["killed"] / scored if scored else 0.0
    lines = [f"{len(results)} mutants: {count['killed']} killed, {count['survived']} survived, "
             f"{count['build-failed']} did not build; score {count['killed']}/{scored} = {score:.1f} %"]
    for r in results:
        if r["status"] == "survived":
            lines.append(f"  SURVIVED {r['id']} ({r['file']}): {r['why']}")
        if r["status"] == "build-failed":
            lines.append(f"  DID NOT BUILD {r['id']} ({r['file']})")
    return "\n".join(lines), score


def tree_unchanged(files, snapshots):
    return all((ROOT / f).read_bytes() == snapshots[f] for f in files)


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--list", action="store_true", help="print the mutants and exit")
    parser.add_argument("--build", default="build", help="configured build folder (default build/)")
    parser.add_argument("--only", help="comma-separated mutant ids")
    parser.add_argument("--json", help="write the results to this file as JSON")
    parser.add_argument("--timeout", type=int, default=900, help="seconds per test executable run (default 900)")
    parser.add_argument("--mutants", default=str(DEFAULT_LIST), help="the mutant list (default tests/mutants.json)")
    parser.add_argument("--no-baseline", action="store_true", help="skip the run on the unmutated tree")
    parser.add_argument("--include-equivalent", action="store_true", help="run the mutants marked equivalent too")
    parser.add_argument("--min-score", type=float, help="exit with status 3 when the score (percent) is below this")
    return parser.parse_args()


def select(mutants, args):
    if args.only:
        wanted = args.only.split(",")
        unknown = set(wanted) - {m["id"] for m in mutants}
        if unknown:
            sys.exit("unknown mutant ids: " + ", ".join(sorted(unknown)))
        return [m for m in mutants if m["id"] in wanted]
    return mutants


def main():
    args = parse_args()
    mutants = load_mutants(pathlib.Path(args.mutants))
    if args.list:
        print_list(mutants)
        return 0
    build_dir = pathlib.Path(args.build)
    build_dir = build_dir if build_dir.is_absolute() else ROOT / build_dir
    chosen = select(mutants, args)
    equivalent = [m for m in chosen if m.get("equivalent") and not args.include_equivalent]
    to_run = [m for m in chosen if m not in equivalent]
    to_run.sort(key=lambda m: m["file"])  # consecutive mutants of one file rebuild less
    files = sorted({m["file"] for m in to_run})
    snapshots = {f: (ROOT / f).read_bytes() for f in files}
    signal.signal(signal.SIGTERM, on_sigterm)
    start = time.time()
    results = []
    try:
        if not args.no_baseline:
            baseline(to_run, build_dir, args.timeout)
        for i, m in enumerate(to_run, 1):
            t0 = time.time()
            outcome = apply_and_test(m, build_dir, args.timeout)
            entry = {"id": m["id"], "file": m["file"], "part": part_of(m), "why": m["why"],
                     "seconds": round(time.time() - t0, 1), **outcome}
            results.append(entry)
            print(f"[{i}/{len(to_run)}] {entry['status']:<12} {m['id']} ({entry['seconds']} s) {outcome['detail'][:160]}",
                  flush=True)
    except (KeyboardInterrupt, Interrupted):
        print("interrupted; the files are restored", file=sys.stderr)
    finally:
        if not tree_unchanged(files, snapshots):
            print("ERROR: a mutated file differs from its original", file=sys.stderr)
            return 2
    print("rebuilding the original sources ...", flush=True)
    build(build_dir, sorted({t for m in to_run for t in m["targets"]}), [])
    text, score = summary(results)
    print(text)
    for m in equivalent:
        print(f"  EQUIVALENT (not run) {m['id']}: {m['equivalent']}")
    minutes = (time.time() - start) / 60
    print(f"wall time {minutes:.1f} min")
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(
            {"results": results, "equivalent": [{"id": m["id"], "reason": m["equivalent"]} for m in equivalent],
             "score_percent": round(score, 1), "minutes": round(minutes, 1)}, indent=2) + "\n")
    if len(results) != len(to_run):
        return 1
    return 3 if args.min_score is not None and score < args.min_score else 0


if __name__ == "__main__":
    sys.exit(main())
