#!/bin/sh
# Runs each libFuzzer target of a fuzz build for a fixed time: `make fuzz` calls it.
# Usage: scripts/run-fuzzers.sh BUILD_DIR SECONDS TARGET...
# - The committed seeds (fuzz/corpus/TARGET) are read but never written: libFuzzer adds new
#   inputs to the first corpus folder only, here the scratch folder BUILD_DIR/corpus/TARGET.
# - Crash, leak, timeout and out-of-memory inputs go to BUILD_DIR/artifacts/TARGET-*.
# - First the inputs that once crashed the target (fuzz/regressions/TARGET/, the findings listed
#   in docs/robustness.md) are replayed once each; a failure there fails the target.
# - Logs go to BUILD_DIR/logs/TARGET.log; one summary line per target is printed and appended to
#   BUILD_DIR/fuzz-summary.txt. The exit status is 1 when any target failed.
set -u
if [ $# -lt 3 ]; then
    echo "usage: $0 BUILD_DIR SECONDS TARGET..." >&2
    exit 2
fi
build=$1
seconds=$2
shift 2
source_dir=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$build/artifacts" "$build/logs"
status=0
for target in "$@"; do
    binary="$build/fuzz/$target"
    scratch="$build/corpus/$target"
    log="$build/logs/$target.log"
    mkdir -p "$scratch"
    regressions="$source_dir/fuzz/regressions/$target"
    if [ -d "$regressions" ]; then
        if ! "$binary" "$regressions"/* >"$build/logs/$target.regressions.log" 2>&1; then
            line="$target: FAILED on a past finding (see $build/logs/$target.regressions.log)"
            echo "$line"
            echo "$(date -u +%Y-%m-%dT%H:%M:%SZ) $line" >>"$build/fuzz-summary.txt"
            status=1
            continue
        fi
    fi
    # (the loop's word list was expanded once: reusing "$@" for the flags is safe)
    set -- -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
        -artifact_prefix="$build/artifacts/$target-"
    if [ -f "$source_dir/fuzz/dict/$target.dict" ]; then
        set -- "$@" -dict="$source_dir/fuzz/dict/$target.dict"
    fi
    # The command-line target prints help and error text; close its stdout and stderr
    # (libFuzzer and the sanitizers keep reporting on a duplicate of stderr).
    if [ "$target" = fuzz_cli ]; then set -- "$@" -close_fd_mask=3; fi
    echo "fuzzing $target for $seconds s (log: $log)"
    start=$(date +%s)
    "$binary" "$@" "$scratch" "$source_dir/fuzz/corpus/$target" >"$log" 2>&1
    result=$?
    elapsed=$(( $(date +%s) - start ))
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    coverage=$(grep -o 'cov: [0-9]* ft: [0-9]* corp: [0-9]*/[0-9]*[a-zA-Z]*' "$log" | tail -n 1)
    verdict=ok
    if [ $result -ne 0 ]; then verdict="FAILED (exit $result, see $log)"; status=1; fi
    line="$target: ${elapsed}s, ${runs:-?} executions, ${coverage:-no coverage line}, $verdict"
    echo "$line"
    echo "$(date -u +%Y-%m-%dT%H:%M:%SZ) $line" >>"$build/fuzz-summary.txt"
done
exit $status
