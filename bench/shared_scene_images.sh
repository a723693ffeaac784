#!/usr/bin/env bash
# Render the shared scenes ($MCRENDER_SCENES, default ../shared/scenes) at reduced size and
# write small PNGs of ours beside the references' into docs/images/shared/, for the README.
# Usage: bench/shared_scene_images.sh [SPP]   (default 256; about 5 minutes on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
SCENES=${MCRENDER_SCENES:-../shared/scenes}
SPP=${1:-256}
OUT=docs/images/shared
mkdir -p "$OUT"
cargo build --release -q -p mcrender
M=target/release/mcrender

# scene, width, height, downsampling factor of the Tungsten reference
while read -r name w h f; do
  [ -f "$SCENES/$name/scene-v4.pbrt" ] || { echo "SKIPPED $name: not in $SCENES"; continue; }
  $M render "$SCENES/$name/scene-v4.pbrt" --resolution "${w}x${h}" --spp "$SPP" --max-depth 65 \
     --seed 7 -q -o "$OUT/$name-mcrender.exr"
  $M convert "$OUT/$name-mcrender.exr" "$OUT/$name-mcrender.png"
  $M convert "$SCENES/$name/TungstenRender.exr" "$OUT/$name-tungsten.png" --downsample "$f"
  $M diff "$OUT/$name-mcrender.exr" "$SCENES/$name/TungstenRender.exr" --downsample-b "$f" | sed "s/^/$name: /"
  rm "$OUT/$name-mcrender.exr"
done <<'LIST'
cornell-box 256 256 4
coffee 200 250 4
LIST

# veach-mis as the file is written (max depth 3), beside Mitsuba 3's render of the same
# description; Tungsten's reference was rendered with other settings (see
# crates/cli/tests/shared_scenes.rs), so it is shown but not diffed here.
$M convert "$SCENES/veach-mis/TungstenRender.exr" "$OUT/veach-mis-tungsten.png" --downsample 4
$M render "$SCENES/veach-mis/scene-v4.pbrt" --resolution 320x180 --spp "$SPP" --seed 7 -q -o "$OUT/veach-mis-depth3.exr"
$M convert "$OUT/veach-mis-depth3.exr" "$OUT/veach-mis-mcrender-depth3.png"
$M convert scenes/references/veach-mis-mitsuba-320x180.exr "$OUT/veach-mis-mitsuba-depth3.png"
$M diff "$OUT/veach-mis-depth3.exr" scenes/references/veach-mis-mitsuba-320x180.exr | sed "s/^/veach-mis vs Mitsuba: /"
rm "$OUT/veach-mis-depth3.exr"
