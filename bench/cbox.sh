#!/usr/bin/env bash
# Side-by-side benchmark: the Cornell box at 256x256, same spp and depth, rendered by
# mcrender and by Mitsuba 3 (llvm_ad_rgb, scalar_rgb, and llvm_ad_rgb held to AVX2) in one run,
# 2 threads each. Prints one table; the ratio columns are what to compare across machines (of
# the same vector extensions: see the CPU line), not the seconds.
# relMSE is against ../shared/reference/cornell-box-256.exr; efficiency = 1 / (relMSE x time).
#
# Usage: bench/cbox.sh [SPP]   (default 256). Needs ../shared (peers/, scenes/) beside the repo.
set -euo pipefail
cd "$(dirname "$0")/.."
SPP="${1:-256}"
RES=256
THREADS=2
SHARED="${SHARED:-$(cd .. && pwd)/shared}"
VENV="${PEERS_VENV:-/tmp/peers-venv}"
OUT="$(mktemp -d)"

if [ ! -x "$VENV/bin/python" ] || ! "$VENV/bin/python" -c "import mitsuba" 2>/dev/null; then
    echo "installing Mitsuba 3 into $VENV (see $SHARED/peers/README.md)..." >&2
    (apt-get update -qq && apt-get install -y -qq libllvm19) >&2 || echo "warning: could not install libllvm19; the llvm variant may fail" >&2
    python3 -m venv "$VENV" && "$VENV/bin/pip" install -q mitsuba numpy >&2
fi

# MC=path/to/mcrender measures that binary instead of building this tree (before/after runs).
if [ -z "${MC:-}" ]; then
    cargo build --release -q -p mcrender
    MC=target/release/mcrender
fi

run_mitsuba() { # variant, image name, then optionally a script to run the peers script through
    local variant="$1" name="$2"
    shift 2
    "$VENV/bin/python" "$@" "$SHARED/peers/mitsuba_render.py" --scene "$SHARED/scenes/cornell-box/mitsuba/scene_v3.xml" \
        --res "$RES" --spp "$SPP" --max-depth 65 --variant "$variant" --threads "$THREADS" --out "$OUT/$name.exr" 2>/dev/null | tail -n 1
}

run_mcrender() { # name, then extra options
    local name="$1"; shift
    # Warm-up render (page cache, CPU frequency), then the timed one.
    "$MC" render scenes/cornell-box/scene-v4.pbrt --resolution 16x16 --spp 4 -o "$OUT/warm.exr" -q 2>/dev/null
    "$MC" render scenes/cornell-box/scene-v4.pbrt --resolution "${RES}x${RES}" --spp "$SPP" --max-depth 65 \
        --threads "$THREADS" -o "$OUT/$name.exr" -q "$@" 2>&1 | tail -n 1
}

rel_mse() { # image: relative MSE against the shared Mitsuba reference (12,800 spp), by `mcrender diff`
    if [ -f "$1" ]; then
        "$MC" diff "$1" "$SHARED/reference/cornell-box-256.exr" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["rel_mse"])'
    else
        echo nan
    fi
}

echo "Cornell box ${RES}x${RES}, ${SPP} spp, max depth 65, ${THREADS} threads; $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), $(date -u +%Y-%m-%dT%H:%MZ)"
# The CPU and its vector extensions: Mitsuba's llvm variant runs 16 paths per instruction
# where AVX-512 is present, 8 with AVX2, so ratios are comparable only between like CPUs.
echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'); $(grep -o -w -E 'avx2|avx512f|avx512vl' /proc/cpuinfo | sort -u | tr '\n' ' ')"
# Mitsuba's script uses its independent sampler and its path tracer's Russian roulette (from
# the fifth bounce, survival min(max throughput, 0.95)) and splats each sample through its
# tent filter: the `splat rr=mitsuba` row is like for like. The first row is mcrender's
# default (pbrt-v4's roulette, from the second bounce; filter sampling), the Sobol' row what
# the scene file asks for, and the last mcrender row the best we have (Sobol' and splatting).
mc_line="$(run_mcrender mc-independent --sampler independent)"
mc_rr_line="$(run_mcrender mc-independent-rr --sampler independent --rr mitsuba)"
mc_sobol_line="$(run_mcrender mc-sobol --sampler sobol)"
mc_splat_line="$(run_mcrender mc-splat-rr --sampler independent --rr mitsuba --reconstruction splat)"
mc_sobol_splat_line="$(run_mcrender mc-sobol-splat-rr --sampler sobol --rr mitsuba --reconstruction splat)"
llvm_json="$(run_mitsuba llvm_ad_rgb mitsuba-llvm_ad_rgb || true)"
# The llvm variant held to AVX2 (8 lanes; bench/mitsuba_avx2.py): on a CPU with AVX-512 it
# shows how much of its lead is the 16-lane kernels. The ratios stay over the native llvm row.
llvm_avx2_json="$(run_mitsuba llvm_ad_rgb mitsuba-llvm-avx2 bench/mitsuba_avx2.py || true)"
scalar_json="$(run_mitsuba scalar_rgb mitsuba-scalar_rgb || true)"
errors="$(for f in mc-independent mc-independent-rr mc-sobol mc-splat-rr mc-sobol-splat-rr mitsuba-llvm_ad_rgb mitsuba-scalar_rgb mitsuba-llvm-avx2; do rel_mse "$OUT/$f.exr"; done | tr '\n' ' ')"

python3 - "$RES" "$SPP" "$errors" "$mc_line" "$mc_rr_line" "$mc_sobol_line" "$mc_splat_line" "$mc_sobol_splat_line" "$llvm_json" "$scalar_json" "$llvm_avx2_json" <<'PY'
import json, math, re, sys
res, spp, errors = int(sys.argv[1]), int(sys.argv[2]), [float(e) for e in sys.argv[3].split()]
mc_lines, peer_lines = sys.argv[4:9], sys.argv[9:12]
names = ["mcrender independent", "mcrender indep. rr=mitsuba", "mcrender sobol", "mcrender splat rr=mitsuba",
         "mcrender sobol splat rr=mit.", "mitsuba llvm_ad_rgb", "mitsuba scalar_rgb", "mitsuba llvm, AVX2 only"]
llvm = len(mc_lines)
times = []
for line in mc_lines:
    m = re.search(r"in ([0-9.]+) s", line)
    if not m:
        sys.exit(f"could not read mcrender's summary line: {line!r}")
    times.append(float(m.group(1)))
for js in peer_lines:
    try:
        times.append(json.loads(js)["wall_s"])
    except Exception:
        times.append(None)
base_t = times[llvm]
eff = [1 / (e * t) if t and e > 0 and math.isfinite(e) else None for e, t in zip(errors, times)]
base_e = eff[llvm]
ratio = lambda a, b: f"{a / b:.2f}" if a and b else "n/a"
# time / llvm: lower is faster; efficiency = 1 / (relMSE x time), over llvm's: higher is better.
print(f"{'renderer':<28}{'time (s)':>9}{'M paths/s':>11}{'time / llvm':>13}{'relMSE':>11}{'efficiency / llvm':>19}")
for name, t, e, f in zip(names, times, errors, eff):
    if t is None:
        print(f"{name:<28}{'failed':>9}")
        continue
    print(f"{name:<28}{t:>9.2f}{res * res * spp / t / 1e6:>11.2f}{ratio(t, base_t):>13}{e:>11.2e}{ratio(f, base_e):>19}")
PY
rm -rf "$OUT"
