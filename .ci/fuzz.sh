#!/usr/bin/env bash
# CI: the libFuzzer targets of fuzz/ (docs/fuzzing.md), each for a bounded time on a scratch
# copy of the committed corpus fuzz/corpus/<target>/. Fails (nonzero exit) on a build failure,
# a crash (panic, abort, stack overflow), a time-out of one input, an out-of-memory, or a run
# that did not execute (no "Done N runs" line, no inputs). The inputs a run finds are thrown
# away; a failing input is printed (hex) in the log and kept under $BUMPSIM_FUZZ_KEEP if set.
#
# Built without cargo-fuzz: cargo-fuzz is only a driver that sets these RUSTFLAGS and runs
# the binary, and installing it costs a compile of its own (5 min 18 s measured here).
# The flags are cargo-fuzz's defaults (sancov module pass, inline 8-bit counters, PC table,
# compare tracing, stack depth, --cfg fuzzing, --target so that build scripts and proc macros
# are not instrumented) with debug assertions and overflow checks on, and without
# AddressSanitizer: the inputs only reach safe Rust (the pipeline, ron, png, ply-rs-bw), the
# sanitizer adds to the build and slows every execution, and libFuzzer's RSS limit catches
# memory blow-ups without it. These are stable rustc options: no nightly is needed.
# BUMPSIM_FUZZ_ASAN=1 adds -Zsanitizer=address (with RUSTC_BOOTSTRAP=1) for a local run.
# The build is the release profile at opt-level 1 without debug info (the pipeline and its
# 110 dependencies: the longest part of this script); BUMPSIM_FUZZ_OPT_LEVEL=3 for long runs.
#
#   BUMPSIM_FUZZ_SECONDS  per target (default 45)
#   BUMPSIM_FUZZ_TARGETS  default "config set obj ply png nv2a"
#   BUMPSIM_FUZZ_JOBS     targets run at once (default: the number of cores, at most 2)
#   BUMPSIM_FUZZ_KEEP     a directory to keep each target's grown corpus and findings in
#   BUMPSIM_FUZZ_TARGET_DIR  the build's target directory (default target/fuzz)
#   BUMPSIM_FUZZ_TIMEOUT  seconds one input may take (default 10)
#   BUMPSIM_FUZZ_RSS_MB   memory limit of a target process in MB (default 4096)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
secs=${BUMPSIM_FUZZ_SECONDS:-45}
timeout=${BUMPSIM_FUZZ_TIMEOUT:-10}
rss=${BUMPSIM_FUZZ_RSS_MB:-4096}
# libFuzzer takes 0 for "no limit": a bounded run needs positive numbers
for v in "$secs" "$timeout" "$rss"; do
    [[ "$v" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: expected a positive number, got '$v'" >&2; exit 1; }
done
targets=${BUMPSIM_FUZZ_TARGETS:-"config set obj ply png nv2a"}
jobs=${BUMPSIM_FUZZ_JOBS:-$(nproc)}
[ "$jobs" -gt 2 ] && [ -z "${BUMPSIM_FUZZ_JOBS:-}" ] && jobs=2
triple=$(rustc -vV | sed -n 's/^host: //p')
[ -n "$triple" ] || { echo "fuzz.sh: cannot tell the host triple from rustc -vV" >&2; exit 1; }

flags="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4"
flags+=" -Cllvm-args=-sanitizer-coverage-inline-8bit-counters"
flags+=" -Cllvm-args=-sanitizer-coverage-pc-table"
flags+=" -Cllvm-args=-sanitizer-coverage-trace-compares"
flags+=" -Cllvm-args=-sanitizer-coverage-stack-depth"
flags+=" --cfg fuzzing -Cdebug-assertions -Coverflow-checks"
if [ "${BUMPSIM_FUZZ_ASAN:-0}" = 1 ]; then
    flags+=" -Zsanitizer=address"
    export RUSTC_BOOTSTRAP=1
fi
# its own target directory: other RUSTFLAGS than the suite's build
export CARGO_TARGET_DIR=${BUMPSIM_FUZZ_TARGET_DIR:-$root/target/fuzz}
export CARGO_PROFILE_RELEASE_OPT_LEVEL=${BUMPSIM_FUZZ_OPT_LEVEL:-1}
export CARGO_PROFILE_RELEASE_DEBUG=${BUMPSIM_FUZZ_DEBUG:-0}
start=$(date +%s)
echo "fuzz.sh: building the targets ($targets) for $triple"
RUSTFLAGS="$flags" cargo build --manifest-path fuzz/Cargo.toml --locked --release \
    --target "$triple" --bins
built=$(date +%s)
echo "fuzz.sh: build took $((built - start)) s"

scratch=$(mktemp -d "${TMPDIR:-/tmp}/bumpsim-fuzz.XXXXXX")
trap 'rm -rf "$scratch"' EXIT

# One target: copy its corpus, run libFuzzer, check the log. Prints one summary line; the
# exit status is the verdict.
fuzz_one() {
    local t=$1 dir="$scratch/$1"
    local bin="$CARGO_TARGET_DIR/$triple/release/$t"
    mkdir -p "$dir/corpus" "$dir/artifacts" "$dir/tmp"
    [ -x "$bin" ] || { echo "$t: FAIL: no binary $bin"; return 1; }
    cp "$root/fuzz/corpus/$t/"* "$dir/corpus/"
    local seeds
    seeds=$(find "$dir/corpus" -type f | wc -l)
    [ "$seeds" -gt 0 ] || { echo "$t: FAIL: fuzz/corpus/$t is empty"; return 1; }
    local rc=0
    # the targets write their input files under TMPDIR: keep them in the scratch directory
    TMPDIR="$dir/tmp" nice -n 5 "$bin" "$dir/corpus" \
        -max_total_time="$secs" -timeout="$timeout" -rss_limit_mb="$rss" -max_len=65536 \
        -print_final_stats=1 -artifact_prefix="$dir/artifacts/" \
        >"$dir/log" 2>&1 || rc=$?
    local runs
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/log" | tail -1)
    local found
    found=$(find "$dir/artifacts" -type f | head -1)
    if [ -n "${BUMPSIM_FUZZ_KEEP:-}" ]; then
        mkdir -p "$BUMPSIM_FUZZ_KEEP/$t"
        cp -r "$dir/corpus" "$dir/artifacts" "$dir/log" "$BUMPSIM_FUZZ_KEEP/$t/"
    fi
    if [ "$rc" -ne 0 ] || [ -n "$found" ] || ! grep -q '^Done [0-9]* runs' "$dir/log" \
        || [ -z "$runs" ] || [ "$runs" -lt "$seeds" ]; then
        echo "$t: FAIL: libFuzzer exit $rc, ${runs:-no} executions"
        grep -E 'ERROR|panicked|Test unit written|SUMMARY|deadly|timeout|out-of-memory' \
            "$dir/log" | head -20 || true
        tail -40 "$dir/log"
        if [ -n "$found" ]; then
            echo "$t: the input ($(wc -c <"$found") bytes, $found):"
            head -c 4096 "$found" | od -A d -t x1z | head -80
        fi
        return 1
    fi
    local cov
    cov=$(grep -o 'cov: [0-9]*' "$dir/log" | tail -1)
    echo "$t: ok: $runs executions in $secs s from $seeds seeds, $cov," \
        "$(find "$dir/corpus" -type f | wc -l) inputs at the end"
}

# the targets, $jobs at a time; each one's verdict collected
pids=()
names=()
fail=0
for t in $targets; do
    while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do sleep 1; done
    fuzz_one "$t" >"$scratch/$t.out" 2>&1 &
    pids+=($!)
    names+=("$t")
done
for i in "${!pids[@]}"; do
    if ! wait "${pids[$i]}"; then fail=1; fi
    cat "$scratch/${names[$i]}.out"
done
echo "fuzz.sh: $(( $(date +%s) - start )) s in all (build $((built - start)) s)"
if [ "$fail" -ne 0 ]; then
    echo "fuzz.sh: a fuzz target failed (docs/fuzzing.md: replay the input, add it to" \
        "tests/bad_input.rs, fix it)" >&2
    exit 1
fi
