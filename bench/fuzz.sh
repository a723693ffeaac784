#!/usr/bin/env bash
# Run one cargo-fuzz target for a given time, at the lowest priority (the machine is shared).
#
#   [FUZZ_NICE=19] bench/fuzz.sh TARGET SECONDS [extra libFuzzer flags...]
#   bench/fuzz.sh list
#
# TARGET: tokenizer, parser, loader, ply, png, exr, pfm, tga, obj, gltf, mitsuba
# (fuzz/fuzz_targets/). FUZZ_NICE is the niceness (default 19, the lowest priority). Needs a
# nightly toolchain and cargo-fuzz (`cargo install cargo-fuzz`). The working corpus grows in
# fuzz/corpus/TARGET (seeded from fuzz/seeds/TARGET and fuzz/regressions/TARGET); crashes land
# in fuzz/artifacts/TARGET. A crash input, once fixed, belongs in fuzz/regressions/TARGET, which
# `cargo test -p mcrender-formats --test fuzz_corpus` replays on stable.
# The last lines printed are libFuzzer's summary: executions (stat::number_of_executed_units),
# and the final "cov:" / "ft:" figures are its coverage (edges, features).
set -euo pipefail
cd "$(dirname "$0")/../fuzz"
targets="tokenizer parser loader ply png exr pfm tga obj gltf mitsuba"
if [[ "${1:-}" == list || $# -lt 2 ]]; then
    echo "usage: bench/fuzz.sh TARGET SECONDS [libFuzzer flags]; targets: $targets" >&2
    [[ "${1:-}" == list ]] && exit 0 || exit 2
fi
target=$1 seconds=$2
shift 2
[[ " $targets " == *" $target "* ]] || { echo "unknown target $target (have: $targets)" >&2; exit 2; }
mkdir -p "corpus/$target" "artifacts/$target"
seed_dirs=()
for d in "seeds/$target" "regressions/$target"; do
    [[ -d $d ]] && seed_dirs+=("$d")
done
# -rss_limit_mb: the loader's own limit is 256 MiB (mcrender_formats::fuzzing::MEMORY_LIMIT);
# anything far past it is a finding. -timeout: an input taking longer is a hang.
exec nice -n "${FUZZ_NICE:-19}" cargo +nightly fuzz run "$target" "corpus/$target" "${seed_dirs[@]}" -- \
    -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -max_len=1048576 \
    -print_final_stats=1 -artifact_prefix="artifacts/$target/" "$@"
