#!/usr/bin/env bash
# Side-by-side benchmark: the Cornell box at 256x256, same spp and depth, rendered by
# mcrender and by Mitsuba 3 (llvm_ad_rgb and scalar_rgb) in one run, 2 threads each.
# Prints one table; the ratio column is what to compare across machines, not the seconds.
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

run_mitsuba() { # variant
    "$VENV/bin/python" "$SHARED/peers/mitsuba_render.py" --scene "$SHARED/scenes/cornell-box/mitsuba/scene_v3.xml" \
        --res "$RES" --spp "$SPP" --max-depth 65 --variant "$1" --threads "$THREADS" --out "$OUT/mitsuba-$1.exr" 2>/dev/null | tail -n 1
}

run_mcrender() { # sampler
    # Warm-up render (page cache, CPU frequency), then the timed one.
    "$MC" render scenes/cornell-box/scene-v4.pbrt --resolution 16x16 --spp 4 -o "$OUT/warm.exr" -q 2>/dev/null
    "$MC" render scenes/cornell-box/scene-v4.pbrt --resolution "${RES}x${RES}" --spp "$SPP" --max-depth 65 \
        --sampler "$1" --threads "$THREADS" -o "$OUT/mcrender-$1.exr" -q 2>&1 | tail -n 1
}

echo "Cornell box ${RES}x${RES}, ${SPP} spp, max depth 65, ${THREADS} threads; $(nproc) cores, $(date -u +%Y-%m-%dT%H:%MZ)"
# Mitsuba's script uses its independent sampler: that row is like for like; the Sobol' row is
# what the scene file asks for.
mc_line="$(run_mcrender independent)"
mc_sobol_line="$(run_mcrender sobol)"
llvm_json="$(run_mitsuba llvm_ad_rgb || true)"
scalar_json="$(run_mitsuba scalar_rgb || true)"

python3 - "$mc_line" "$llvm_json" "$scalar_json" "$RES" "$SPP" "$mc_sobol_line" <<'PY'
import json, re, sys
mc_line, llvm, scalar, res, spp, mc_sobol = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]), int(sys.argv[5]), sys.argv[6]
rows = []
for name, line in (("mcrender independent", mc_line), ("mcrender sobol", mc_sobol)):
    m = re.search(r"in ([0-9.]+) s", line)
    if not m:
        sys.exit(f"could not read mcrender's summary line: {line!r}")
    rows.append((name, float(m.group(1))))
for name, js in (("mitsuba llvm_ad_rgb", llvm), ("mitsuba scalar_rgb", scalar)):
    try:
        rows.append((name, json.loads(js)["wall_s"]))
    except Exception:
        rows.append((name, None))
base = rows[2][1]
print(f"{'renderer':<22}{'time (s)':>10}{'M paths/s':>12}{'time / mitsuba llvm':>22}")
for name, t in rows:
    if t is None:
        print(f"{name:<22}{'failed':>10}")
        continue
    ratio = f"{t / base:.2f}" if base else "n/a"
    print(f"{name:<22}{t:>10.2f}{res * res * spp / t / 1e6:>12.2f}{ratio:>22}")
PY
rm -rf "$OUT"
