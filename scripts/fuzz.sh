#!/usr/bin/env bash
# Runs every libFuzzer harness of tests/fuzz, each from a seed corpus made of the repository's own
# files (tests/data, tests/fuzz/seeds and tests/fuzz/regressions), and fails on any crash, leak,
# sanitizer report, failed check or time-out. The harnesses must be built already
# (scripts/sanitize.sh builds them in build-san with FDMSURF_FUZZ=ON; docs/reliability.md).
#
# Two modes:
#   scripts/fuzz.sh                    # CI: a fixed number of runs per harness (about 60 s each
#                                      # on a 2-core VM), seed 1, from the seeds alone, 2 at a time
#   FDMSURF_FUZZ_SECONDS=3600 scripts/fuzz.sh fuzz_pdb fuzz_mmcif   # the long run: S seconds
#                                      # per harness, a random seed, the corpus kept between runs
# The CI mode does a fixed amount of work from a fixed seed, whatever the machine's speed; its
# runs are close to, not exactly, the same each time (coverage counted in the program's own
# threads varies, so the corpora differ by a few percent). New ground is the long run's work,
# and its findings become regression inputs (tests/fuzz/regressions) that every CI run replays.
#
# Environment: FDMSURF_SAN_BUILD_DIR (default build-san), FDMSURF_FUZZ_SECONDS (the long run;
# unset: the CI mode), FDMSURF_FUZZ_SEED (CI mode, default 1), FDMSURF_FUZZ_RUNS_SCALE (CI mode:
# multiplies every harness's runs, default 1), FDMSURF_FUZZ_JOBS (harnesses at once, default 2).
# The long run's corpora grow in BUILD/fuzz/corpus/NAME; the CI mode starts each from an empty
# BUILD/fuzz/ci-corpus/NAME. A crash leaves BUILD/fuzz/NAME-crash-* and the harness's log
# BUILD/fuzz/NAME.log, and this script prints the command that replays it.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

build_dir=${FDMSURF_SAN_BUILD_DIR:-build-san}
seconds=${FDMSURF_FUZZ_SECONDS:-}
seed=${FDMSURF_FUZZ_SEED:-1}
scale=${FDMSURF_FUZZ_RUNS_SCALE:-1}
jobs=${FDMSURF_FUZZ_JOBS:-2}
for setting in "FDMSURF_FUZZ_SECONDS=$seconds" "FDMSURF_FUZZ_SEED=$seed" \
               "FDMSURF_FUZZ_RUNS_SCALE=$scale" "FDMSURF_FUZZ_JOBS=$jobs"; do
    if [[ ! ${setting#*=} =~ ^[0-9]*$ ]]; then
        echo "fuzz.sh: $setting is not a whole number" >&2
        exit 2
    fi
done
if [[ -n $seconds ]] && ((10#$seconds == 0)); then  # sanitize.sh's "no fuzzing" (libFuzzer
    echo "fuzz.sh: FDMSURF_FUZZ_SECONDS=0, no fuzzing"  # would read 0 as no time limit)
    exit 0
fi
if ((10#$seed == 0 || 10#$scale == 0 || 10#${jobs:-0} == 0)); then  # libFuzzer: seed 0 = random
    echo "fuzz.sh: FDMSURF_FUZZ_SEED, FDMSURF_FUZZ_RUNS_SCALE and FDMSURF_FUZZ_JOBS must be at least 1" >&2
    exit 2
fi
work="$build_dir/fuzz"

# CI mode: runs per harness, about 60 s each on the 2-core VM of docs/reliability.md (its
# executions per second with the seeds alone); a slower machine stops at the time cap, after a
# prefix of the same runs.
declare -A ci_runs=(
    [fuzz_pdb]=45000 [fuzz_mmcif]=45000 [fuzz_pqr]=500000 [fuzz_xyzr]=250000
    [fuzz_xyzrn]=150000 [fuzz_stdin]=45000 [fuzz_ply]=400000 [fuzz_obj]=450000
    [fuzz_off]=500000 [fuzz_stl]=400000 [fuzz_glb]=300000 [fuzz_msms]=300000
    [fuzz_options]=200000)
ci_cap_seconds=240
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
    if [[ -z $seconds && -z ${ci_runs[$h]:-} ]]; then
        echo "fuzz.sh: $h has no run count for the CI mode (ci_runs in this script)" >&2
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
        fuzz_pdb)   cp $data/1crn.pdb $data/3al1.pdb $data/lenient/*.pdb "$dir"/
                    gzip -dc $data/4hhb.pdb.gz | head -c 60000 >"$dir/4hhb-head.pdb" ;;
        fuzz_mmcif) cp $data/1crn.cif $data/lenient/*.cif "$dir"/
                    gzip -dc $data/4yvs.cif.gz | head -c 60000 >"$dir/4yvs-head.cif" ;;
        fuzz_xyzr)  cp $data/1crn.xyzr "$dir"/ ;;
        fuzz_xyzrn) cp $data/1crn.xyzrn "$dir"/ ;;
        fuzz_stdin) cp $data/1crn.pdb $data/1crn.xyzr $data/1crn.xyzrn $data/1crn.cif \
                       $data/lenient/*.pqr "$dir"/
                    gzip -9c $data/1crn.pdb >"$dir/1crn.pdb.gz"
                    gzip -9c $data/1crn.xyzr >"$dir/1crn.xyzr.gz" ;;
    esac
    if [[ -d $seeds/$h ]]; then cp "$seeds/$h"/* "$dir"/; fi
    # the inputs that once broke this target (tests/fuzz/regressions, replayed by the suite)
    find tests/fuzz/regressions -name "$h-*" -exec cp {} "$dir"/ \;
    echo "$dir"
}

run_one() {
    local h=$1 seed_files corpus log mode_args
    seed_files=$(seed_dir "$h")
    log="$work/$h.log"
    if [[ -n $seconds ]]; then
        corpus="$work/corpus/$h"
        mode_args=(-max_total_time="$seconds")
    else
        corpus="$work/ci-corpus/$h"
        rm -rf "$corpus"
        mode_args=(-reload=0 -seed="$seed" -runs=$((${ci_runs[$h]} * scale)) -max_total_time=$ci_cap_seconds)
    fi
    mkdir -p "$corpus"
    # -rss_limit_mb: a reader that needs more than 2.5 GB for a fuzzed input of at most
    # -max_len bytes is a finding. -timeout: one input taking 30 s is a hang.
    if "$build_dir/tests/fuzz/$h" "${mode_args[@]}" -timeout=30 -rss_limit_mb=2560 \
           -max_len=65536 -print_final_stats=1 -artifact_prefix="$work/$h-" \
           "$corpus" "$seed_files" >"$log" 2>&1; then
        local runs cov corp
        runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" || true)
        cov=$(grep -E '^#[0-9]+[[:space:]]+DONE' "$log" | sed -n 's/.*cov: \([0-9]*\).*/\1/p' | tail -1 || true)
        corp=$(find "$corpus" -type f | wc -l)
        local secs
        secs=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -1 || true)
        printf '%-14s ok     %10s runs in %4s s  coverage %6s  corpus %6s\n' "$h" "${runs:-?}" \
            "${secs:-?}" "${cov:-?}" "$corp"
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
if [[ -n $seconds ]]; then
    mode="$seconds s each, random seeds, corpora kept in $work/corpus"
else
    mode="fixed runs (x$scale) each, seed $seed, from the seeds alone, at most $ci_cap_seconds s each"
fi
echo "fuzz.sh: ${#harnesses[@]} harnesses, $mode, $jobs at a time ($(date -u +%FT%TZ), $(git rev-parse --short HEAD 2>/dev/null || echo '?'))"
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
