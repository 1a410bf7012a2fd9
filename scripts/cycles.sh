#!/usr/bin/env bash
# bumprad against an independent renderer: Blender builds a textured, normal-mapped room with an
# emissive panel and exports it as glTF (bench/cycles/room.py), Cycles renders that file twice
# at two seeds (bench/cycles/render.py), and bumprad-bench-truth renders the same file at
# bumprad's defaults and measures it, and bumprad's own path tracer, against Cycles.
#   scripts/cycles.sh [--spp 4096] [--size 256] [--out out/cycles] [--scene SCENE.json]
# With --scene, a bumprad scene file of quads (scenes/cornell.json) instead: Blender builds it
# as it stands (bench/cycles/bumprad_scene.py) and bumprad renders the file itself.
# Installs Blender (Debian's) when missing. About 20 minutes on 2 cores at the defaults.
set -euo pipefail
cd "$(dirname "$0")/.."
spp=4096 size=256 out=out/cycles scene=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --spp) spp=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --scene) scene=$2; shift 2 ;;
    *) echo "usage: scripts/cycles.sh [--spp N] [--size PIXELS] [--out DIR] [--scene S.json]" >&2
      exit 2 ;;
  esac
done
if ! command -v blender >/dev/null || ! python3 -c "import numpy" 2>/dev/null; then
  sudo=""
  [[ $(id -u) -ne 0 ]] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
    blender python3-numpy
fi
scripts/setup.sh
mkdir -p "$out"
blender=(blender -b --factory-startup --python-exit-code 1 --python)
# A bumprad scene file is Lambert already: only the glTF room is rendered a second way, with
# Cycles' Principled BSDF.
if [[ -n "$scene" ]]; then
  model=$scene kinds=(lambert)
else
  model=$out/room.glb kinds=(lambert principled)
  "${blender[@]}" bench/cycles/room.py -- "$model" --size "$size" >"$out/blender.log" 2>&1
fi
for seed in 1 2; do
  for materials in "${kinds[@]}"; do
    [[ $seed == 2 && $materials == principled ]] && continue
    start=$SECONDS
    "${blender[@]}" bench/cycles/render.py -- "$model" "$out/cycles-$materials-$seed.exr" \
      --spp "$spp" --size "$size" --seed "$seed" --materials "$materials" >>"$out/blender.log" 2>&1
    echo "Cycles ($materials BSDFs, seed $seed): $spp samples a pixel at $size across, $((SECONDS - start)) s"
  done
done
echo "against Cycles with Lambert surfaces (a glTF file's metallic 0, as bumprad reads it):"
BUMPRAD_TRUTH_IMAGES="$out/lambert" build/bin/bumprad-bench-truth "$model" \
  --width "$size" --spp 1024 --reference "$out/cycles-lambert-1.exr" \
  --noise-reference "$out/cycles-lambert-2.exr"
[[ -n "$scene" ]] && exit 0
echo "against Cycles with its Principled BSDF (a dielectric's specular coat, Disney diffuse):"
build/bin/bumprad-bench-truth "$model" --width "$size" --no-path-tracer \
  --reference "$out/cycles-principled-1.exr"
