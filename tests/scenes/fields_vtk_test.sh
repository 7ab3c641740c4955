#!/usr/bin/env bash
# output.fields end to end, read by VTK's own XML reader (what ParaView uses) and NumPy:
# an ED run with an obstacle, checkpointed and resumed (the series continues, fields.pvd
# lists each frame once), and a DEM run on its xz plane. Usage: fields_vtk_test.sh GRAINFLOW SCENES_DIR OUT PYTHON
set -euo pipefail
gf=$1 scenes=$2 out=$3 py=$4
check="$(dirname "$0")/check_fields_vtk.py"
quiet=(--set output.mp4=false --set output.png=false --set output.fields=true)
rm -rf "$out" && mkdir -p "$out"
"$gf" run "$scenes/obstacle_quick.toml" -o "$out/ed" --set run.until=4 --set sample.exposure=1 --set 'sample.bins=[40,20]' \
  --set output.checkpoint_every=2 "${quiet[@]}" >/dev/null 2>&1
touch "$out/ed/fields/frame_000099.vti"   # not the run's: a stale frame the resume must drop
"$gf" run --resume "$out/ed" --set run.until=7 >/dev/null 2>&1
[ ! -e "$out/ed/fields/frame_000099.vti" ] || { echo "FAIL: stale frame kept"; exit 1; }
# obstacle_quick: 200 × 100 σ box, 40 × 20 bins of 5 σ.
"$py" "$check" "$out/ed" 40 20 0 0 0 5 5 1 2
[ "$(grep -c '<DataSet' "$out/ed/fields.pvd")" = 7 ] || { echo "FAIL: expected 7 frames after the resume"; exit 1; }
"$gf" run "$scenes/dem_freefall_box.toml" -o "$out/dem" --set run.until=0.03 --set sample.exposure=0.01 \
  --set 'system.group[0].N=500' "${quiet[@]}" >/dev/null 2>&1
# dem_freefall_box: box 0.04 m wide and tall, 20 × 20 bins of two diameters on xz (no
# sample.bins), one cell across its slab y = 0.01 … 0.03 m.
"$py" "$check" "$out/dem" 20 20 0 0.01 0 0.002 0.02 0.002 3
echo "fields_vtk_test: ok"
