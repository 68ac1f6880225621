#!/bin/bash
# fdmsurf on a GPU machine without a build toolchain or package registry: unpacks the bundle
# that bench/gpu/bundle.sh made (.gpu/bundle.tar.gz), finds the NVIDIA Vulkan driver, then
#   1. lists the devices and runs 1CRN once with the validation layer (cold: empty caches);
#   2. times fdm and edt at 0.5 Å on 1CRN, 4HHB, 4YVS, 1AON (one warm-up, REPS timed runs),
#      the 4YVS assembly (317,160 atoms) and 0.25 Å where it fits, sampling device memory;
#   3. compares the GPU meshes of 1CRN and 4HHB with lavapipe's (fdmsurf compare);
#   4. runs the whole GoogleTest suite on the GPU with the validation layer (sharded).
# Results go to $OUT (or ./gpu-out): info.txt, bench.jsonl, compare.jsonl, tests.log,
# and a table from summarize.py at the end. Steps can be chosen: run.sh [bench] [ab] [trace] [fft]
# [tests] (ab: before/after against the bundle's baseline CLI, interleaved, and FDMSURF_TRACE
# runs; fft: bench/fft_multibuffer.cpp, VkFFT's multi-buffer mode against slabs).
set -u
root=$(cd "$(dirname "$0")/../.." && pwd)
out=${OUT:-$root/gpu-out}; mkdir -p "$out"
reps=${REPS:-3}
set_=${BENCH_SET:-1crn.pdb 4hhb.pdb 4yvs.cif.gz 1aon.pdb.gz}
steps=${*:-bench tests}
B=/tmp/fdmsurf-gpu; rm -rf "$B"; mkdir -p "$B"
tar xzf "$root/.gpu/bundle.tar.gz" -C "$B" || { echo "run.sh: no .gpu/bundle.tar.gz (carry it)"; exit 1; }
for f in "$B"/debs/*.deb; do dpkg -x "$f" /; done; ldconfig
export LD_LIBRARY_PATH=$B/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export VK_LAYER_PATH=$B/layers
if ! ls /usr/share/vulkan/icd.d/nvidia_icd*.json /etc/vulkan/icd.d/nvidia_icd*.json >/dev/null 2>&1; then
    icd=$(ls /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd*.json 2>/dev/null | head -1)
    [ -n "$icd" ] && export VK_DRIVER_FILES=$icd VK_ICD_FILENAMES=$icd
fi
# The test binary has the build tree's paths compiled in (tests/data, build/fdmsurf).
compiled_root=$(strings "$B/bin/fdmsurf_tests" | grep -m1 -o '/[^"]*/tests/data' | sed 's#/tests/data##')
if [ -n "$compiled_root" ] && [ "$compiled_root" != "$root" ] && [ ! -e "$compiled_root" ]; then
    mkdir -p "$(dirname "$compiled_root")" && ln -s "$root" "$compiled_root"
fi
mkdir -p "$root/build/tests"
if [ "${KEEP_BUILD:-0}" != 1 ]; then
    cp "$B/bin/fdmsurf" "$root/build/fdmsurf"; ln -sf fdmsurf "$root/build/msms"
    cp "$B/bin/fdmsurf_tests" "$root/build/tests/fdmsurf_tests"
fi
F=$root/build/fdmsurf
D=$B/data
{
    echo "commit: $(cat "$B/commit")"; echo "date: $(date -u +%FT%TZ)"; uname -a
    nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.sm --format=csv
    echo "cpu: $(grep -m1 'model name' /proc/cpuinfo) x $(nproc)"
    echo "icd: ${VK_DRIVER_FILES:-system}"
    "$F" --version; "$F" --list-devices
} > "$out/info.txt" 2>&1
cat "$out/info.txt"

# One timed run: appends its --stats json with wall_ms, peak device memory and labels.
run() {  # label cold|warm args...
    local label=$1 phase=$2; shift 2
    local mem=/tmp/mem.$$; nvidia-smi --query-gpu=memory.used --format=csv,noheader,nounits -lms 20 > $mem 2>/dev/null &
    local smi=$!; sleep 0.1
    rm -f /tmp/m.ply  # replacing a large earlier output would be timed as part of the write
    local t0=$(date +%s%N)
    local js; js=$(timeout ${RUN_TIMEOUT:-120} "$F" "$@" --stats json --quiet 2>/tmp/err.$$); local rc=$?
    local t1=$(date +%s%N)
    kill $smi 2>/dev/null; wait $smi 2>/dev/null
    local peak=$(sort -n $mem | tail -1); local base=$(head -1 $mem)
    python3 - "$label" "$phase" "$rc" $(( (t1 - t0) / 1000 )) "${peak:-0}" "${base:-0}" "$js" /tmp/err.$$ <<'PY' >> "$out/bench.jsonl"
import json, sys
label, phase, rc, wall_us, peak, base, js, errf = sys.argv[1:]
try:
    d = json.loads(js) if js.strip() else {}
except ValueError:
    d = {"unparsed": js[-500:]}
d.update(label=label, phase=phase, rc=int(rc), wall_ms=int(wall_us) / 1000.0,
         gpu_mem_peak_mib=int(peak or 0), gpu_mem_base_mib=int(base or 0),
         stderr=open(errf).read()[-800:])
print(json.dumps(d))
PY
    echo "  $label $phase rc=$rc wall=$(( (t1 - t0) / 1000000 )) ms"
}

if [[ " $steps " == *" bench "* ]]; then
    echo "== cold 1CRN with validation"
    run 1crn-fdm-0.5-validation cold "$D/1crn.pdb" -o /tmp/1crn-gpu.ply --validation
    cp /tmp/1crn-gpu.ply "$out/"
    run 1crn-fdm-0.5 warm "$D/1crn.pdb" -o /tmp/1crn-gpu.ply --validation
    run 4hhb-fdm-0.5-validation warm "$D/4hhb.pdb" -o /tmp/4hhb-gpu.ply --validation
    for s in 1crn 4hhb; do
        "$F" compare "$B/ref/$s-lvp.ply" /tmp/$s-gpu.ply --spacing 0.5 --stats json > /tmp/c.json 2>&1
        python3 -c "import json,sys; d=json.load(open('/tmp/c.json')); d['label']='$s'; print(json.dumps(d))" >> "$out/compare.jsonl" \
            || { echo "compare $s failed:"; cat /tmp/c.json; }
    done
    echo "== 0.5 Å, fdm and edt"
    for s in $set_; do
        n=${s%%.*}
        for m in fdm edt; do
            run $n-$m-0.5 warmup "$D/$s" --method $m -o /tmp/m.ply
            for i in $(seq $reps); do run $n-$m-0.5 warm "$D/$s" --method $m -o /tmp/m.ply; done
        done
    done
    echo "== 4YVS assembly (317,160 atoms), 0.5 Å"
    for m in ${ASSEMBLY_METHODS-fdm edt}; do
        run 4yvs-asm-$m-0.5 warmup "$D/4yvs.cif.gz" --assembly 1 --method $m -o /tmp/m.ply
        for i in 1 2; do run 4yvs-asm-$m-0.5 warm "$D/4yvs.cif.gz" --assembly 1 --method $m -o /tmp/m.ply; done
    done
    echo "== 0.25 Å"
    for s in ${FINE_SET-$set_}; do
        n=${s%%.*}
        for m in fdm edt; do
            run $n-$m-0.25 warmup "$D/$s" --method $m --spacing 0.25 -o /tmp/m.ply
            run $n-$m-0.25 warm "$D/$s" --method $m --spacing 0.25 -o /tmp/m.ply
        done
    done
    rm -f /tmp/m.ply
fi

if [[ " $steps " == *" ab "* ]] && [ -x "$B/bin/fdmsurf-base" ]; then
    # Before/after, interleaved: the baseline CLI (bundle.sh's .gpu/fdmsurf-base) and this one.
    echo "== A/B: base against new, interleaved"
    new=$F
    jobs_=${AB_JOBS:-1crn.pdb fdm;4hhb.pdb fdm;4hhb.pdb edt;4yvs.cif.gz fdm;4yvs.cif.gz edt;1aon.pdb.gz fdm;1aon.pdb.gz edt;4yvs.cif.gz fdm --assembly 1}
    IFS=';' read -ra ab_jobs <<< "$jobs_"
    for job in "${ab_jobs[@]}"; do
        set -- $job; s=$1; m=$2; shift 2; n=${s%%.*}${1:+-asm}
        for v in base new; do
            F=$new; [ $v = base ] && F=$B/bin/fdmsurf-base
            run $n-$m-0.5@$v warmup "$D/$s" --method $m -o /tmp/m.ply "$@"
        done
        for i in $(seq ${AB_REPS:-3}); do
            for v in base new; do
                F=$new; [ $v = base ] && F=$B/bin/fdmsurf-base
                run $n-$m-0.5@$v warm "$D/$s" --method $m -o /tmp/m.ply "$@"
            done
        done
    done
    F=$new
    for s in ${AB_TRACE-1crn.pdb 1aon.pdb.gz}; do
        for m in fdm edt; do
            echo "-- trace: $s $m" >> "$out/trace.txt"
            FDMSURF_TRACE=1 "$F" "$D/$s" --method $m -o /tmp/m.ply --quiet 2>> "$out/trace.txt"
        done
    done
    rm -f /tmp/m.ply
    cat "$out/trace.txt"
fi

if [[ " $steps " == *" trace "* ]]; then
    # Where the host time goes (FDMSURF_TRACE=1), and whether the driver's shader cache is used.
    echo "== traces" | tee -a "$out/trace.txt"
    for s in 1aon.pdb.gz 4yvs.cif.gz 1crn.pdb; do
        for i in 1 2; do
            rm -f /tmp/m.ply
            echo "-- trace: $s fdm, run $i" >> "$out/trace.txt"
            FDMSURF_TRACE=1 "$F" "$D/$s" -o /tmp/m.ply --quiet 2>> "$out/trace.txt"
        done
    done
    echo "-- shader caches: HOME=$HOME" >> "$out/trace.txt"
    du -s "$HOME"/.cache/* 2>&1 >> "$out/trace.txt"; ls -la "$HOME/.cache/nvidia" "$HOME/.cache/nvidia"/* 2>&1 | head -20 >> "$out/trace.txt"
    for i in 1 2 3; do
        rm -f /tmp/m.ply
        echo "-- trace: 1aon fdm, __GL_SHADER_DISK_CACHE_SIZE=10 GB, run $i" >> "$out/trace.txt"
        __GL_SHADER_DISK_CACHE_SIZE=10000000000 __GL_SHADER_DISK_CACHE_SKIP_CLEANUP=1 FDMSURF_TRACE=1 \
            "$F" "$D/1aon.pdb.gz" -o /tmp/m.ply --quiet 2>> "$out/trace.txt"
    done
    rm -f /tmp/m.ply
    grep -E -- "^--|filter|structure read|read back|cavities|mesh written|statistics|vertex properties" "$out/trace.txt"
fi

if [[ " $steps " == *" fft "* ]] && [ -x "$B/bin/fdmsurf_bench_fft_multibuffer" ]; then
    # VkFFT's multi-buffer mode against the slab mode's FFTs, with its round-trip check (wrong
    # transforms on llvmpipe: docs/performance.md); one buffer where the device's binding
    # range holds the whole grid.
    echo "== VkFFT multi-buffer against slabs (1AON's grid, 4HHB's)"
    for args in "--buffers 2 384x343x448 245 2" "--buffers 1 384x343x448 245 2" \
                "--buffers 2 192x168x168 96 2"; do
        echo "-- $args"
        timeout ${RUN_TIMEOUT:-120} "$B/bin/fdmsurf_bench_fft_multibuffer" --reps ${REPS:-3} $args
    done 2>&1 | tee "$out/fft_multibuffer.txt"
fi

if [[ " $steps " == *" tests "* ]]; then
    echo "== GoogleTest suite on the GPU, validation layer on (FDMSURF_REQUIRE_DEVICE=1)"
    shards=${SHARDS:-8}
    for i in $(seq 0 $((shards - 1))); do
        FDMSURF_REQUIRE_DEVICE=1 GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$i \
            timeout ${TEST_TIMEOUT:-300} "$root/build/tests/fdmsurf_tests" > /tmp/shard.$i.log 2>&1 &
    done
    wait
    cat /tmp/shard.*.log > "$out/tests.log"
    grep -h -E '^\[  (PASSED|FAILED|SKIPPED) +\]|tests? ran' /tmp/shard.*.log
    grep -h -E '^\[  FAILED  \]' /tmp/shard.*.log | sort -u | head -40
fi
python3 "$root/bench/gpu/summarize.py" "$out" | tee "$out/summary.md"
