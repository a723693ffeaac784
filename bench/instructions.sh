#!/usr/bin/env bash
# Instruction counts of two mcrender binaries on the same render, by valgrind's cachegrind:
# unlike times, they do not move with the load of a shared machine, so a change of a few
# percent shows. Prints each binary's total, the ratio, and the functions whose counts
# changed most (self counts, inlined code included in its caller: two builds that inline
# differently move counts between functions without changing the total much).
#
# Usage: bench/instructions.sh BEFORE AFTER [render options...]
#   default options: the Cornell box at 64x64, 4 spp, max depth 65, 1 thread, independent
#   sampler, --rr mitsuba. Example: bench/instructions.sh /tmp/mc-old target/release/mcrender
#   --reconstruction splat
# Installs valgrind with apt-get when it is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { echo "usage: bench/instructions.sh BEFORE AFTER [render options...]" >&2; exit 2; }
BEFORE="$1"
AFTER="$2"
shift 2
for b in "$BEFORE" "$AFTER"; do
    [ -x "$b" ] || { echo "bench/instructions.sh: $b is not an executable" >&2; exit 2; }
done
if ! command -v valgrind >/dev/null; then
    echo "installing valgrind..." >&2
    (apt-get update -qq && apt-get install -y -qq valgrind) >&2
fi
OUT="$(mktemp -d)"
trap 'rm -rf "$OUT"' EXIT
OPTS=(scenes/cornell-box/scene-v4.pbrt --resolution 64x64 --spp 4 --max-depth 65 --threads 1
    --sampler independent --rr mitsuba "$@")

for side in before after; do
    bin="$BEFORE"
    [ "$side" = after ] && bin="$AFTER"
    valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file="$OUT/$side.cg" \
        "$bin" render "${OPTS[@]}" -o "$OUT/$side.exr" -q >/dev/null 2>"$OUT/$side.log" \
        || { cat "$OUT/$side.log" >&2; exit 1; }
done
cmp -s "$OUT/before.exr" "$OUT/after.exr" && same="identical" || same="different"

python3 - "$OUT/before.cg" "$OUT/after.cg" "$same" "${OPTS[*]}" <<'PY'
import collections, sys

def self_counts(path):
    """Instructions per function (the cachegrind file's fn= blocks, first event column)."""
    counts, fn = collections.Counter(), None
    for line in open(path):
        if line.startswith("fn="):
            fn = line[3:].strip()
        elif fn and line[:1].isdigit():
            parts = line.split()
            if len(parts) >= 2:
                counts[fn] += int(parts[1])
    return counts

before, after = self_counts(sys.argv[1]), self_counts(sys.argv[2])
tb, ta = sum(before.values()), sum(after.values())
print(f"render {sys.argv[4]}")
print(f"instructions: before {tb:,}, after {ta:,}, after / before {ta / tb:.4f}; images {sys.argv[3]}")
changes = sorted(((after[k] - before[k], k) for k in set(before) | set(after)), key=lambda c: -abs(c[0]))
print(f"{'change':>14} {'before':>14} {'after':>14}  function")
for d, k in changes[:15]:
    print(f"{d:>+14,} {before[k]:>14,} {after[k]:>14,}  {k[:90]}")
PY
