#!/bin/sh
# A Middlebury 2014 pair from ../shared/data -> a coloured point cloud in
# metres, from the scene's own calib.txt:
#
#   examples/middlebury2014_point_cloud.sh [SCENE] [OUTDIR]
#   (SCENE: adirondack (default), jadeplant, motorcycle, motorcyclee, piano, pianol)
#
# Writes OUTDIR/SCENE_points.ply (one point per valid pixel), SCENE_mesh.ply
# (the 2.5D mesh in metres), SCENE_depth.pfm (metres) and SCENE_stats.json
# (with the ROS DisparityImage fields). Open the PLY files in MeshLab,
# CloudCompare or Open3D. Needs build/tristereo (scripts/build.sh).
set -eu
repo=$(cd "$(dirname "$0")/.." && pwd)
scene=${1:-adirondack}
out=${2:-point-cloud-out}
data="$repo/../shared/data/middlebury2014"
dir="$data/$scene"
if [ ! -f "$dir/calib.txt" ]; then
  echo "no $dir/calib.txt: put ../shared beside the project (scenes: $(cut -f1 "$data/datasets.tsv" 2>/dev/null | tail -n +2 | tr '\n' ' '))" >&2
  exit 1
fi
ndisp=$(awk -v s="$scene" '$1 == s { print $4 }' "$data/datasets.tsv")
mkdir -p "$out"
"$repo/build/tristereo" match "$dir/left.png" "$dir/right.png" --ndisp "$ndisp" \
  --calib "$dir/calib.txt" --points "$out/${scene}_points.ply" --mesh "$out/${scene}_mesh.ply" \
  --depth "$out/${scene}_depth.pfm" --stats "$out/${scene}_stats.json"
echo "point cloud: $out/${scene}_points.ply"
