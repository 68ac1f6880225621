#!/usr/bin/env bash
# Runs every libFuzzer harness of tests/fuzz for a bounded time, each from a seed corpus made of
# the repository's own files (tests/data, tests/fuzz/seeds and tests/fuzz/regressions), and
# fails on any crash, leak, sanitizer report, failed check or time-out. The harnesses must be built already
# (scripts/sanitize.sh builds them in build-san with FDMSURF_FUZZ=ON; docs/reliability.md).
#
#   scripts/fuzz.sh                    # 60 s per harness, 2 at a time
#   FDMSURF_FUZZ_SECONDS=3600 scripts/fuzz.sh fuzz_pdb fuzz_mmcif   # the long run, some harnesses
#
# Environment: FDMSURF_SAN_BUILD_DIR (default build-san), FDMSURF_FUZZ_SECONDS (default 60),
# FDMSURF_FUZZ_JOBS (harnesses run at once, default 2). The corpora grow in
# BUILD/fuzz/corpus/NAME (kept between runs); a crash leaves BUILD/fuzz/NAME-crash-* and the
# harness's log BUILD/fuzz/NAME.log, and this script prints the command that replays it.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

build_dir=${FDMSURF_SAN_BUILD_DIR:-build-san}
seconds=${FDMSURF_FUZZ_SECONDS:-60}
jobs=${FDMSURF_FUZZ_JOBS:-2}
work="$build_dir/fuzz"
seeds=tests/fuzz/seeds
data=tests/data

all=(fuzz_pdb fuzz_mmcif fuzz_pqr fuzz_xyzr fuzz_xyzrn fuzz_stdin
     fuzz_ply fuzz_obj fuzz_off fuzz_stl fuzz_glb fuzz_msms fuzz_options)
if (($#)); then harnesses=("$@"); else harnesses=("${all[@]}"); fi

for h in "${harnesses[@]}"; do
    if [[ ! -x $build_dir/tests/fuzz/$h ]]; then
        echo "fuzz.sh: $build_dir/tests/fuzz/$h is not built (scripts/sanitize.sh builds the harnesses)" >&2
        exit 1
    fi
done

# Seed files for each harness: the repository's structures and meshes (gzip ones decompressed
# where the harness reads text), plus the small hand-made seeds of tests/fuzz/seeds/NAME.
seed_dir() {
    local h=$1 dir="$work/seeds/$h"
    rm -rf "$dir"
    mkdir -p "$dir"
    case $h in
        fuzz_pdb)   cp $data/1crn.pdb $data/3al1.pdb "$dir"/
                    gzip -dc $data/4hhb.pdb.gz | head -c 60000 >"$dir/4hhb-head.pdb" ;;
        fuzz_mmcif) cp $data/1crn.cif "$dir"/
                    gzip -dc $data/4yvs.cif.gz | head -c 60000 >"$dir/4yvs-head.cif" ;;
        fuzz_xyzr)  cp $data/1crn.xyzr "$dir"/ ;;
        fuzz_xyzrn) cp $data/1crn.xyzrn "$dir"/ ;;
        fuzz_stdin) cp $data/1crn.pdb $data/1crn.xyzr $data/1crn.xyzrn $data/1crn.cif "$dir"/
                    gzip -9c $data/1crn.pdb >"$dir/1crn.pdb.gz"
                    gzip -9c $data/1crn.xyzr >"$dir/1crn.xyzr.gz" ;;
    esac
    if [[ -d $seeds/$h ]]; then cp "$seeds/$h"/* "$dir"/; fi
    # the inputs that once broke this target (tests/fuzz/regressions, replayed by the suite)
    find tests/fuzz/regressions -name "$h-*" -exec cp {} "$dir"/ \;
    echo "$dir"
}

run_one() {
    local h=$1 seed corpus log
    seed=$(seed_dir "$h")
    corpus="$work/corpus/$h"
    log="$work/$h.log"
    mkdir -p "$corpus"
    # -rss_limit_mb: a reader that needs more than 2.5 GB for a fuzzed input of at most
    # -max_len bytes is a finding. -timeout: one input taking 30 s is a hang.
    if "$build_dir/tests/fuzz/$h" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2560 \
           -max_len=65536 -print_final_stats=1 -artifact_prefix="$work/$h-" \
           "$corpus" "$seed" >"$log" 2>&1; then
        local runs cov corp
        runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" || true)
        cov=$(grep -E '^#[0-9]+[[:space:]]+DONE' "$log" | sed -n 's/.*cov: \([0-9]*\).*/\1/p' | tail -1 || true)
        corp=$(find "$corpus" -type f | wc -l)
        printf '%-14s ok     %10s runs  coverage %6s  corpus %6s\n' "$h" "${runs:-?}" "${cov:-?}" "$corp"
    else
        printf '%-14s FAILED (log: %s)\n' "$h" "$log"
        grep -E 'ERROR|SUMMARY|runtime error|fuzz check failed|Test unit written|uncaught' "$log" | head -8 | sed 's/^/    /' || true
        local artifact
        artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | head -1 || true)
        if [[ -n $artifact ]]; then echo "    replay: $build_dir/tests/fuzz/$h $artifact"; fi
        return 1
    fi
}

mkdir -p "$work"
supp="$(pwd)/tests/sanitizers"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$supp/lsan.supp:print_suppressions=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export ASAN_SYMBOLIZER_PATH=${ASAN_SYMBOLIZER_PATH:-$(command -v llvm-symbolizer || command -v llvm-symbolizer-14 || true)}
echo "fuzz.sh: ${#harnesses[@]} harnesses, $seconds s each, $jobs at a time ($(date -u +%FT%TZ), $(git rev-parse --short HEAD 2>/dev/null || echo '?'))"
status=0
pids=()
results="$work/results"
rm -rf "$results"
mkdir -p "$results"
for h in "${harnesses[@]}"; do
    while (($(jobs -rp | wc -l) >= jobs)); do wait -n || true; done
    (if run_one "$h" >"$results/$h" 2>&1; then echo 0; else echo 1; fi >"$results/$h.rc") &
done
wait
for h in "${harnesses[@]}"; do
    cat "$results/$h"
    [[ $(cat "$results/$h.rc") == 0 ]] || status=1
done
if ((status)); then echo "fuzz.sh: a harness failed (each crash becomes a regression test: docs/reliability.md)" >&2; fi
exit $status
