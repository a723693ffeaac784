#!/usr/bin/env bash
# The integrators at equal time (issue 8, item 7): `mcrender compare --integrators` on
# Veach's bidirectional room and on the Cornell box, in one run, printing both tables.
# Each integrator gets the same render time; relative MSE is against the scene's reference
# box-downsampled to the render's size (as crates/cli/tests/bdpt_scenes.rs does); efficiency
# = 1 / (relMSE x time). The seconds depend on the machine and its load; compare the
# efficiency column within one run.
#
# Usage: bench/integrators.sh [SECONDS]   (default 10 per integrator and scene)
#   MCRENDER_SCENES: Bitterli scenes with veach-bidir/ (default ../shared/scenes)
#   SHARED_REFERENCE: directory with cornell-box-256.exr (default ../shared/reference)
#   THREADS (default 2), RES (default 128), OUT (default a temporary directory)
set -euo pipefail
cd "$(dirname "$0")/.."
BUDGET="${1:-10}"
RES="${RES:-128}"
THREADS="${THREADS:-2}"
SCENES="${MCRENDER_SCENES:-../shared/scenes}"
REFS="${SHARED_REFERENCE:-../shared/reference}"
OUT="${OUT:-$(mktemp -d)}"
mkdir -p "$OUT"

cargo build --release -q -p mcrender
MC=target/release/mcrender

# MLT at equal time gets the mutations per pixel that two short calibration renders
# (not counted) predict fit in the budget; see crates/core/src/lab/integrators.rs.
INTEGRATORS=path,bdpt,lightpath,mlt,sppm

# reduce REFERENCE SIZE OUT: box-downsample a square reference to RES x RES.
reduce() {
    local size="$2" factor
    factor=$((size / RES))
    if [ $((factor * RES)) -ne "$size" ]; then
        echo "error: $1 is ${size}x${size}, not a multiple of RES=$RES" >&2
        exit 1
    fi
    "$MC" convert "$1" "$3" --downsample "$factor" >/dev/null
}

run() { # title scene reference name
    echo
    echo "== $1: ${RES}x${RES}, ${BUDGET} s per integrator, ${THREADS} threads; $(nproc) cores, $(date -u +%Y-%m-%dT%H:%MZ)"
    "$MC" compare "$2" --integrators "$INTEGRATORS" --resolution "${RES}x${RES}" --time-budget "$BUDGET" \
        --threads "$THREADS" --reference "$3" -o "$OUT/$4" 2>/dev/null
}

reduce "$SCENES/veach-bidir/TungstenRender.exr" 1024 "$OUT/veach-bidir-ref.exr"
reduce "$REFS/cornell-box-256.exr" 256 "$OUT/cornell-ref.exr"
run "veach-bidir (max depth 7 from the file; reference Tungsten, 1024x1024 box-downsampled)" \
    "$SCENES/veach-bidir/scene-v4.pbrt" "$OUT/veach-bidir-ref.exr" veach-bidir
run "Cornell box (max depth 65; reference Mitsuba 3, 12800 spp, 256x256 box-downsampled)" \
    scenes/cornell-box/scene-v4.pbrt "$OUT/cornell-ref.exr" cornell
echo
echo "images, contact sheets and convergence plots in $OUT"
