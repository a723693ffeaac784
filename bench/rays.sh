#!/usr/bin/env bash
# Ray throughput of mcrender's BVH beside Embree 4 (PyPI `embreex`), on the same files in
# the same run: a 1M-triangle mesh and three ray sets (camera, incoherent, shadow), made by
# bench/rays_gen.py. For 1 and 2 threads, each side runs twice, alternating (A B A B), and
# the faster run of each is kept. The hits of both are compared (closest hit: t within a
# relative 1e-4; any hit: same answer) and the disagreements counted.
# The ratio column is what to compare across machines, not the rays per second.
#
# Usage: bench/rays.sh [TRIANGLES] [RAYS]   (defaults 1000000 1000000)
# Creates a Python venv with numpy and embreex under target/bench-venv on first use.
set -euo pipefail
cd "$(dirname "$0")/.."
TRIS="${1:-1000000}"
NRAYS="${2:-1000000}"
VENV=target/bench-venv
DATA="target/rays-${TRIS}-${NRAYS}"
REPEAT="${REPEAT:-3}"

if [ ! -x "$VENV/bin/python" ] || ! "$VENV/bin/python" -c "import embreex, numpy" 2>/dev/null; then
    echo "installing numpy and embreex into $VENV..." >&2
    python3 -m venv "$VENV" && "$VENV/bin/pip" install -q numpy embreex >&2
fi
PY="$VENV/bin/python"
# MC=path/to/mcrender measures that binary instead of building this tree (before/after runs).
if [ -z "${MC:-}" ]; then
    cargo build --release -q -p mcrender
    MC=target/release/mcrender
fi
[ -f "$DATA/shadow.bin" ] || "$PY" bench/rays_gen.py "$DATA" --triangles "$TRIS" --rays "$NRAYS" >&2
OUT="$(mktemp -d)"
trap 'rm -rf "$OUT"' EXIT

echo "bench/rays.sh: $TRIS-triangle bumpy sphere, $NRAYS rays per set; $(nproc) cores, $(date -u +%Y-%m-%dT%H:%MZ)"
# The CPU and its vector extensions: Mitsuba's llvm variant runs 16 paths per instruction
# where AVX-512 is present, 8 with AVX2, so ratios are comparable only between like CPUs.
echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'); $(grep -o -w -E 'avx2|avx512f|avx512vl' /proc/cpuinfo | sort -u | tr '\n' ' ')"
echo "(each figure the best of $REPEAT passes within a run and of 2 alternating runs)"
rows="$OUT/rows.txt"
: > "$rows"
for threads in 1 2; do
    # A row is a ray set, optionally with mcrender tracing it in packets of eight
    # (`--packets`; the Embree side traces one ray at a time in every row).
    for row in camera camera+packets incoherent shadow; do
        set="${row%+packets}"
        packets=()
        [ "$row" != "$set" ] && packets=(--packets)
        query=closest
        [ "$set" = shadow ] && query=any
        for round in 1 2; do
            "$MC" bench-rays "$DATA/mesh.ply" "$DATA/$set.bin" --query "$query" --threads "$threads" \
                --repeat "$REPEAT" --hits "$OUT/mc.hits" "${packets[@]}" > "$OUT/mc-$round.txt"
            "$PY" bench/rays_embree.py "$DATA/mesh.ply" "$DATA/$set.bin" --query "$query" --threads "$threads" \
                --repeat "$REPEAT" --hits "$OUT/em.hits" > "$OUT/em-$round.txt"
        done
        "$PY" - "$threads" "$row" "$query" "$OUT" >> "$rows" <<'PY'
import json, re, sys
import numpy as np
threads, set_, query, out = sys.argv[1:5]
mc_rate, mc_build = 0.0, float("inf")
em_rate, em_build = 0.0, float("inf")
for r in (1, 2):
    text = open(f"{out}/mc-{r}.txt").read()
    mc_rate = max(mc_rate, float(re.search(r"([0-9.]+) M rays/s", text).group(1)))
    mc_build = min(mc_build, float(re.search(r"built in ([0-9.]+) s", text).group(1)))
    js = json.loads(open(f"{out}/em-{r}.txt").read().strip().splitlines()[-1])
    em_rate = max(em_rate, js["m_rays_per_s"])
    em_build = min(em_build, js["build_s"])
    tris = js["triangles"]
a = np.fromfile(f"{out}/mc.hits", "<f4")
b = np.fromfile(f"{out}/em.hits", "<f4")
both_miss = np.isinf(a) & np.isinf(b)
with np.errstate(invalid="ignore"):
    close = np.abs(a - b) <= 1e-4 * np.maximum(1.0, np.abs(b))
disagree = int((~(both_miss | close)).sum())
print(f"{threads}\t{set_}\t{query}\t{mc_rate:.3f}\t{em_rate:.3f}\t{mc_rate / em_rate:.2f}\t{disagree}\t{len(a)}\t"
      f"{tris / mc_build / 1e6:.2f}\t{tris / em_build / 1e6:.2f}")
PY
    done
done
printf '%-8s%-17s%-9s%14s%14s%10s%16s%16s%16s\n' threads "ray set" query "mcrender M/s" "Embree M/s" ratio "disagreements" "mc build Mt/s" "Embree Mt/s"
while IFS=$'\t' read -r th set q mc em ratio dis n mb eb; do
    printf '%-8s%-17s%-9s%14s%14s%10s%16s%16s%16s\n' "$th" "$set" "$q" "$mc" "$em" "$ratio" "$dis / $n" "$mb" "$eb"
done < "$rows"
echo "ratio = mcrender / Embree (above 1: mcrender faster). camera+packets: mcrender traces the camera rays"
echo "in packets of eight consecutive rays of the file, Embree one at a time (embreex has no packet query)."
echo "Embree's build always uses all cores (TBB) and"
echo "includes a first one-ray query; with 2 threads Embree traces from 2 processes (embreex holds the GIL)."
echo "The machine may be shared: compare ratios from one run, not seconds across runs."
