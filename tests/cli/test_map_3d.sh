#!/usr/bin/env bash
# The early time mapped onto a 3D quarter (hydro::mapAxisymmetricToQuarter, docs/solver.md): one
# deck, a 0.1 kg Comp B charge under 3 cm of EMI sand and a fixed disc 0.1 m above it, run in 2D
# axisymmetric and in the 3D quarter at 10 mm on the same fine early-time block. The 3D run, its
# early time taken onto the quarter, gives the 2D run's impulse on the disc within 2% at 0.5 ms;
# both books close to round-off.
# Usage: test_map_3d.sh EJECTA
ejecta=$(realpath "$1")
source "$(dirname "$0")/lib.sh"
cat > disc.toml <<'DECK'
title = "early time onto a 3D quarter vs the 2D run continued"
geometry = "axisymmetric"
gravity = false
end_time_s = 0.0005
[mesh]
cell_size_m = 0.01
grading = 1.1
core_radius_m = 0.24
core_bottom_m = -0.25
core_top_m = 0.16
domain_radius_m = 0.3
domain_bottom_m = -0.25
domain_top_m = 0.2
[[soil]]
wet_density_kg_m3 = 1370.0
moisture = 0.07
top_m = 0.0
bottom_m = -0.25
[charge]
explosive = "CompB"
mass_kg = 0.1
shape = "cylinder"
height_to_diameter = 0.3333333
depth_of_burial_m = 0.03
detonation = "bottom"
[early]
block_margin_m = 0.06   # the same block in 2D and 3D (2D stops it three cells below the disc)
[target]
kind = "disc"
radius_m = 0.3
thickness_m = 0.03
standoff_m = 0.1
motion = "fixed"
DECK
"$ejecta" run disc.toml --no-plot --quiet --out rz > rz.out 2>&1
"$ejecta" run disc.toml --set 'geometry="3d-quarter"' --no-plot --quiet --out q > q.out 2>&1
read -r i2 i3 mapping books <<< "$(python3 - <<'PY'
import json
a, b = (json.load(open(f + '/summary.json')) for f in ('rz', 'q'))
print(a['result']['impulse_Ns'], b['result']['impulse_Ns'], b['early_time'].get('mapping', '-').replace(' ', '_'),
      max(abs(a['energy']['imbalance_fraction']), abs(b['energy']['imbalance_fraction'])))
PY
)"
echo "impulse on the disc: 2D $i2 N s, 3D $i3 N s; mapping: $mapping; books $books"
check "the 3D run maps the axisymmetric early time onto its quarter" "[[ $mapping == axisymmetric_block_onto_the_3D_quarter ]]"
check "both runs used the same fine block" "[[ \"\$(grep -o 'fine block[^(]*' rz.out)\" == \"\$(grep -o 'fine block[^(]*' q.out)\" ]]"
check "3D impulse within 2% of the 2D run's" "python3 -c 'import sys; sys.exit(abs($i3 / $i2 - 1) > 0.02)'"
check "energy books close in both (imbalance <= 1e-10 of the charge)" "python3 -c 'import sys; sys.exit($books > 1e-10)'"
finish
