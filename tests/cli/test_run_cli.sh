#!/usr/bin/env bash
# `ejecta run` as a user runs it: the run folder's outputs, a checkpoint whose restart reproduces
# the uninterrupted run bit for bit, and deck errors that name the key and leave nothing behind.
ejecta=$1
source "$(dirname "$0")/lib.sh"
# (a coarse early-time block keeps this quick under the sanitizers; the default is 20 cells per charge height)
common=(emi-flat-7 --cell-size 25 --set end_time_s=0.0006 --set 'output.field_times_s=[0.0004]' --set 'output.profile_times_s=[0.0002,0.0005]'
        --set early.cells_per_charge_height=8 --quiet)

"$ejecta" run "${common[@]}" --checkpoint-at 0.0003 --out a > a.txt 2> a.err
rc=$?
check "run exits 0 (rc $rc: $(tail -1 a.err))" "[[ $rc -eq 0 ]]"
for f in summary.json history.csv gauges.csv surface_profiles.csv fields.pvd plots.png checkpoint.bin; do
  check "a/$f written" "[[ -s a/$f ]]"
done
check "a field snapshot" "ls a/fields/field_0000.vtr > /dev/null 2>&1 && grep -q RectilinearGrid a/fields/field_0000.vtr"
check "summary parses, impulse > 0" "python3 -c 'import json; d=json.load(open(\"a/summary.json\")); assert d[\"result\"][\"impulse_Ns\"] > 0; assert d[\"deck\"][\"end_time_s\"] == 0.0006'"
# the numerics' version the results came from (raised with every change that alters them; revision 10: the predictor)
check "summary names the solver revision" "python3 -c 'import json; r=json.load(open(\"a/summary.json\"))[\"run\"][\"solver_revision\"]; assert isinstance(r, int) and r >= 10, r'"
check "energy books close: imbalance <= 1e-10 of the charge's energy, every term reported" "python3 -c '
import json; e = json.load(open(\"a/summary.json\"))[\"energy\"]
assert abs(e[\"imbalance_fraction\"]) <= 1e-10, e[\"imbalance_fraction\"]
for k in (\"initial_J\", \"final_J\", \"work_on_target_J\", \"boundary_flux_J\"): assert k in e, k
assert set(e[\"by_material_J\"]) == {\"air\", \"products\", \"soil\"}'"
check "the early time ran on a fine block and was mapped" "python3 -c '
import json; e = json.load(open(\"a/summary.json\"))[\"early_time\"]
assert e[\"used\"] and e[\"cells_per_charge_height\"] >= 8 and e[\"map_time_s\"] > 0, e'"
check "no temporary files left" "[[ -z \$(find . -name '.*tmp*') ]]"

# A material's name is written into the snapshot's XML as it is, whatever it holds (escaped).
"$ejecta" run "${common[@]}" --set 'soil.0.name="sand <wet> & \"x\""' --no-plot --out xml-name > /dev/null 2>&1
check "a soil named with XML's own characters: the snapshot parses and names it" "python3 -c '
import xml.etree.ElementTree as ET
names = [a.get(\"Name\") for a in ET.parse(\"xml-name/fields/field_0000.vtr\").getroot().iter(\"DataArray\")]
assert \"alpha_sand <wet> & \\\"x\\\"\" in names, names'"

# A plate above the uniform core is run, and said to be: in the log and in summary.json (the
# deck's own plate, in its core, has none).
"$ejecta" run "${common[@]}" --set target.standoff_m=0.3 --no-plot --out high > /dev/null 2> high.err
check "a plate above the core: the run warns, naming the key" "grep -q 'run: warning: mesh.core_top_m: the target.s loaded face reaches z = 0.300 m' high.err"
check "a plate above the core: summary.json lists it, the deck's plate none" "python3 -c '
import json
assert len(json.load(open(\"high/summary.json\"))[\"mesh_warnings\"]) == 1
assert json.load(open(\"a/summary.json\"))[\"mesh_warnings\"] == []'"

# A batch job's log: --quiet drops the self-rewriting line, --log-every says the progress as plain lines.
"$ejecta" run "${common[@]}" --log-every 0.00001 --no-plot --out logged > /dev/null 2> logged.err
check "--log-every: plain progress lines with the time left" "grep -q '^run: t = .* ms of 0.6 ms, step [0-9]*, wall .* min, left ~.* min, impulse' logged.err"
err=$("$ejecta" run "${common[@]}" --log-every -1 --out bad-log 2>&1 >/dev/null); rc=$?
check "--log-every -1: refused, naming the option (rc $rc)" "[[ $rc -ne 0 && \"\$err\" == *log-every* && ! -e bad-log ]]"

# Output times the early time ran past (its block is not the run mesh) are taken at the map time,
# said so, and recorded at that time (they stopped the run with a negative time step before).
"$ejecta" run "${common[@]}" --set 'output.field_times_s=[0.000001,0.0004]' --set 'output.profile_times_s=[0.000001,0.0005]' --no-plot \
  --out early-out > /dev/null 2> early-out.err
rc=$?
map_t=$(python3 -c 'import json; print("{:.9g}".format(json.load(open("early-out/summary.json"))["early_time"]["map_time_s"]))' 2>/dev/null)
check "outputs within the early time: exit 0 ($(tail -1 early-out.err)), taken at the map time ($map_t s) and said" \
  "[[ $rc -eq 0 ]] && grep -q 'timestep=\"$map_t\" file=\"fields/field_0000.vtr\"' early-out/fields.pvd && [[ -s early-out/fields/field_0000.vtr ]] \
   && head -1 early-out/surface_profiles.csv | grep -q '^r_m,z_m@t' && grep -q 'field_times_s: 1e-06 s is within the early time' early-out.err \
   && grep -q 'profile_times_s: 1e-06 s is within the early time' early-out.err"

# A charge far smaller than the run's cells: the early block's cost is said before its work.
"$ejecta" run "${common[@]}" --set charge.mass_kg=1e-6 --no-plot --out tiny > /dev/null 2> tiny.err &
pid=$!
for _ in $(seq 300); do grep -q 'early time (fine block\|run mesh.s work' tiny.err && break; sleep 0.1; done
kill -TERM $pid 2> /dev/null
wait $pid
check "a 1 mg charge under 25 mm cells: the early block's cost said first" "grep -q 'times the run mesh.s work' tiny.err"

"$ejecta" run "${common[@]}" --restart a/checkpoint.bin --out b --no-plot > b.txt 2> b.err; rc=$?
check "restart exits 0 ($(tail -1 b.err))" "[[ $rc -eq 0 ]]"
check "restart: history bit for bit" "cmp -s a/history.csv b/history.csv"
check "restart: gauges bit for bit" "cmp -s a/gauges.csv b/gauges.csv"
check "restart: surface profiles bit for bit" "cmp -s a/surface_profiles.csv b/surface_profiles.csv"
check "restart: the new folder keeps the checkpoint it started from" "cmp -s a/checkpoint.bin b/checkpoint.bin"
# A restart with other output times takes this deck's after the checkpoint (0.3 ms), numbered after
# the snapshots the earlier run took (the old list's positions once dropped or mislabelled them).
"$ejecta" run "${common[@]}" --set 'output.field_times_s=[0.0001,0.00045,0.0005]' --restart a/checkpoint.bin --out b2 --no-plot > /dev/null 2> b2.err
check "restart with other output times: each after the checkpoint taken at its time ($(tail -1 b2.err))" "python3 -c '
import re
times = [float(t) for t in re.findall(r\"timestep=.([0-9.e-]+).\", open(\"b2/fields.pvd\").read())]
assert times == [0.00045, 0.0005], times' && [[ -s b2/fields/field_0000.vtr && -s b2/fields/field_0001.vtr ]] && ! grep -q 'early time' b2.err"
# An interrupted run's checkpoint, still in its staging folder, restarts into the same place: the
# folder is not cleared first (it was, with the checkpoint in it), and goes once the run has ended.
mkdir .i.staging-999999 && cp a/checkpoint.bin .i.staging-999999/
"$ejecta" run "${common[@]}" --restart .i.staging-999999/checkpoint.bin --out i --no-plot > /dev/null 2> i.err; rc=$?
check "restart from an interrupted run's staging folder ($(tail -1 i.err))" "[[ $rc -eq 0 ]] && cmp -s a/history.csv i/history.csv && [[ -s i/checkpoint.bin && ! -e .i.staging-999999 ]]"
# A folder of other files is not a run's to replace; a mount point cannot be renamed.
mkdir -p notes && echo keep > notes/notes.md
err=$("$ejecta" run "${common[@]}" --out notes 2>&1 >/dev/null)
check "--out at a folder of other files: exit 2 naming it, the files kept" "[[ $? -eq 2 ]] && grep -q 'not an ejecta run folder' <<< \"\$err\" && [[ \$(cat notes/notes.md) == keep ]]"
err=$("$ejecta" run "${common[@]}" --out / 2>&1 >/dev/null)
check "--out /: exit 2 before the run" "[[ $? -eq 2 ]] && grep -q 'out' <<< \"\$err\""

# A free plate moves through the mesh: how far the history's target_z_m (its underside on the mesh)
# has risen by 10 ms is its integrated displacement (within one cell), and the EMI plate at 7%
# rises more than 5 cm.
"$ejecta" run emi-flat-7 --cell-size 40 --set early.enabled=false --quiet --no-plot --out m > m.txt 2> m.err; rc=$?
check "moving plate: run exits 0 ($(tail -1 m.err))" "[[ $rc -eq 0 ]]"
check "moving plate: target_z_m at 10 ms is the displacement within one cell, and over 5 cm" "python3 -c '
import csv, json
d = json.load(open(\"m/summary.json\")); h = list(csv.DictReader(open(\"m/history.csv\")))
z, disp = float(h[-1][\"target_z_m\"]) - float(h[0][\"target_z_m\"]), d[\"result\"][\"plate_displacement_m\"]
assert abs(float(h[-1][\"t_s\"]) - 0.01) < 1e-9
assert abs(z - disp) < 0.04 and z > 0.05, (z, disp)
assert abs(d[\"energy\"][\"imbalance_fraction\"]) < 1e-10'"
err=$("$ejecta" run "${common[@]}" --set charge.mas_kg=1 --out c 2>&1 >/dev/null)
rc=$?
check "unknown key: exit 2 (got $rc)" "[[ $rc -eq 2 ]]"
check "unknown key: names charge.mas_kg ('$err')" "grep -q 'charge.mas_kg' <<< \"\$err\""
check "unknown key: nothing written" "[[ ! -e c ]]"
check "summary echoes the resolved deck: a default the deck leaves out is there" "python3 -c 'import json; d=json.load(open(\"a/summary.json\"))[\"deck\"]; assert d[\"early\"][\"signal_speed_m_s\"] == 6000.0 and d[\"soil\"][0][\"thermal_gamma\"] == -1.0, d'"
err=$("$ejecta" run "${common[@]}" --set $'cfl=0.3\nend_time_s=0.5' --out c 2>&1 >/dev/null)
check "text after a --set value is refused: exit 2 naming the key" "[[ $? -eq 2 ]] && grep -q 'cfl' <<< \"\$err\" && [[ ! -e c ]]"
"$ejecta" run --help-deck > deckhelp.txt
check "--help-deck lists every section's keys with ranges" "grep -q '^soil.N.moisture' deckhelp.txt && grep -q '^target.standoff_m' deckhelp.txt && grep -q 'valid \\[0.05, 0.9\\]' deckhelp.txt"
"$ejecta" run --help-deck html > /dev/null 2>&1
check "--help-deck with an unknown format: exit 2" "[[ $? -eq 2 ]]"
err=$("$ejecta" run "${common[@]}" --set charge.depth_of_burial_m=3 --out c 2>&1 >/dev/null)
check "charge outside the domain: exit 2 naming it" "[[ $? -eq 2 ]] && grep -q depth_of_burial <<< \"\$err\""
err=$("$ejecta" run "${common[@]}" --set 'soil=[{dry_density_kg_m3=1670.0, moisture=0.30}]' --out c 2>&1 >/dev/null)
check "saturation over 100%: exit 2 naming the layer's moisture" "[[ $? -eq 2 ]] && grep -q 'soil.0.moisture' <<< \"\$err\""
for bad in "output.field_times_s=[0.0]" "output.profile_times_s=[0.0005,0.0002]" "output.field_times_s=[-1.0]"; do
  err=$("$ejecta" run "${common[@]}" --set "$bad" --out c 2>&1 >/dev/null)
  check "bad output times ($bad): exit 2 naming the key" "[[ $? -eq 2 ]] && grep -q '${bad%%=*}' <<< \"\$err\""
done
for at in -1 0 0.0006 0.01; do
  err=$("$ejecta" run "${common[@]}" --checkpoint-at $at --out c 2>&1 >/dev/null)
  check "checkpoint at $at s (not inside the run): exit 2" "[[ $? -eq 2 ]] && grep -q 'checkpoint-at' <<< \"\$err\""
done
err=$("$ejecta" run "${common[@]}" --threads 100000 --out c 2>&1 >/dev/null)
check "--threads 100000: exit 2 naming it" "[[ $? -eq 2 ]] && grep -q threads <<< \"\$err\""
err=$("$ejecta" run "${common[@]}" --set soil.99999999999999999999.moisture=0.1 --out c 2>&1 >/dev/null)
check "huge list index: exit 2 naming the key" "[[ $? -eq 2 ]] && grep -q 'soil.99999999999999999999' <<< \"\$err\""
err=$("$ejecta" run "${common[@]}" --restart a/checkpoint.bin --set end_time_s=0.0002 --out c 2>&1 >/dev/null)
check "restart with an end before the checkpoint: exit 2" "[[ $? -eq 2 ]] && grep -q end_time_s <<< \"\$err\""
# a checkpoint is tied to its deck and is checked: another deck, a flipped byte, a cut file,
# something that is not a checkpoint are all refused with exit 2 naming why
err=$("$ejecta" run emi-flat-22 --cell-size 25 --set end_time_s=0.0006 --set early.cells_per_charge_height=8 --quiet --restart a/checkpoint.bin --out c 2>&1 >/dev/null)
check "restart with another deck: exit 2 naming the deck" "[[ $? -eq 2 ]] && grep -q 'another deck' <<< \"\$err\""
cp a/checkpoint.bin flipped.bin
size=$(stat -c %s flipped.bin)
printf '\xff' | dd of=flipped.bin bs=1 seek=$((size / 2)) conv=notrunc status=none
err=$("$ejecta" run "${common[@]}" --restart flipped.bin --out c 2>&1 >/dev/null)
check "restart from a damaged checkpoint: exit 2 (checksum)" "[[ $? -eq 2 ]] && grep -q checksum <<< \"\$err\""
head -c $((size - 100)) a/checkpoint.bin > cut.bin
err=$("$ejecta" run "${common[@]}" --restart cut.bin --out c 2>&1 >/dev/null)
check "restart from a truncated checkpoint: exit 2" "[[ $? -eq 2 ]] && grep -q truncated <<< \"\$err\""
err=$("$ejecta" run "${common[@]}" --restart a/summary.json --out c 2>&1 >/dev/null)
check "restart from a file that is not a checkpoint: exit 2" "[[ $? -eq 2 ]] && grep -q 'not an ejecta checkpoint' <<< \"\$err\""
# ...and so is a driver state that does not fit, behind a valid envelope (the run would index it)
mkdir -p bad && python3 "$(dirname "$0")/damage_driver_state.py" a/checkpoint.bin bad
check "eight damaged driver states written" "[[ \$(ls bad/*.bin | wc -l) -eq 8 ]]"
for f in bad/*.bin; do
  err=$("$ejecta" run "${common[@]}" --restart "$f" --out c 2>&1 >/dev/null)
  check "restart from $f: exit 2 (damaged)" "[[ $? -eq 2 ]] && grep -q 'checkpoint is damaged' <<< \"\$err\""
done
"$ejecta" run "${common[@]}" --restart a/checkpoint.bin --set end_time_s=0.0007 --set 'output.field_times_s=[0.00065]' --out e --no-plot > /dev/null 2> e.err; rc=$?
check "restart running longer with other outputs is allowed ($(tail -1 e.err))" "[[ $rc -eq 0 ]]"
touch plainfile
err=$("$ejecta" run "${common[@]}" --out plainfile/run 2>&1 >/dev/null)
check "a run folder that cannot be made: exit 2 naming --out, in words" "[[ $? -eq 2 ]] && grep -q 'out: cannot create the run folder' <<< \"\$err\" && ! grep -q 'filesystem error' <<< \"\$err\""
err=$("$ejecta" sweep emi-flat-7 --vary cfl=0.4 --out plainfile/sweep 2>&1 >/dev/null)
check "sweep into a folder that cannot be made: exit 2, the path in words" "[[ $? -eq 2 ]] && grep -q 'plainfile/sweep: Not a directory' <<< \"\$err\""
err=$("$ejecta" run emi-flat-7 --cell-size '' --out c 2>&1 >/dev/null)
check "an empty option value: exit 2 naming the option" "[[ $? -eq 2 ]] && grep -q -- '--cell-size' <<< \"\$err\""
err=$("$ejecta" run emi-flat-7 --threads= --out c 2>&1 >/dev/null)
check "an empty --opt= value: exit 2 naming the option" "[[ $? -eq 2 ]] && grep -q -- '--threads' <<< \"\$err\""
err=$(timeout 20 "$ejecta" run /dev/zero --out c 2>&1 >/dev/null)
check "a device as the deck: exit 2 at once" "[[ $? -eq 2 ]] && grep -q 'not a regular file' <<< \"\$err\""
head -c 2000000 /dev/zero | tr '\0' '#' > big.toml
err=$("$ejecta" run big.toml --out c 2>&1 >/dev/null)
check "a deck over 1 MiB: exit 2" "[[ $? -eq 2 ]] && grep -q 'at most' <<< \"\$err\""
# the soil's geometry must mean what the deck says
err=$("$ejecta" run emi-flat-7 --set soil.0.top_m=5 --set soil.0.bottom_m=4 --out c 2>&1 >/dev/null)
check "soil wholly above the domain: exit 2 naming the layer" "[[ $? -eq 2 ]] && grep -q 'soil.0.top_m' <<< \"\$err\""
err=$("$ejecta" run emi-flat-7 --set soil.0.top_m=-0.5 --out c 2>&1 >/dev/null)
check "soil whose top is not the ground (the charge would float): exit 2" "[[ $? -eq 2 ]] && grep -q 'ground is z = 0' <<< \"\$err\""
sed 's/^bottom_m = -0.85/bottom_m = -0.30/' "$(dirname "$ejecta")/../../decks/emi-flat-7.toml" > two.toml
printf '\n[[soil]]\nname = "lower"\nwet_density_kg_m3 = 1370.0\nmoisture = 0.07\ntop_m = -0.2\nbottom_m = -0.85\nradius_m = 0.315\n' >> two.toml
err=$("$ejecta" run two.toml --out c 2>&1 >/dev/null)
check "overlapping soil layers: exit 2 naming them" "[[ $? -eq 2 ]] && grep -q 'overlaps soil.0' <<< \"\$err\""
# The same sand as two layers meeting at -0.31 m (a cell cut between them): the same soil mass as one
# layer, no air below the ground (the lower layer gave way to the air, not to the upper layer).
sed 's/^bottom_m = -0.85/bottom_m = -0.31/' "$(dirname "$ejecta")/../../decks/emi-flat-7.toml" > split.toml
printf '\n[[soil]]\nname = "lower"\nwet_density_kg_m3 = 1370.0\nmoisture = 0.07\ntop_m = -0.31\nbottom_m = -0.85\nradius_m = 0.315\n' >> split.toml
layers=(--cell-size 40 --set end_time_s=0.00002 --set early.enabled=false --set 'output.field_times_s=[0.00002]' --no-plot --quiet)
"$ejecta" run "$(dirname "$ejecta")/../../decks/emi-flat-7.toml" "${layers[@]}" --out one-layer > /dev/null 2>&1
"$ejecta" run split.toml "${layers[@]}" --out two-layers > /dev/null 2>&1
check "two layers of one sand hold the one layer's soil mass at the start (to 1e-12)" "python3 -c '
import csv
a, b = (next(csv.DictReader(open(f + \"/history.csv\"))) for f in (\"one-layer\", \"two-layers\"))
ma, mb = float(a[\"mass_soil_kg\"]), float(b[\"mass_soil_kg\"])
assert ma > 0 and abs(ma - mb) <= 1e-12 * ma, (ma, mb)'"
err=$("$ejecta" run no-such-deck --out c 2>&1 >/dev/null)
check "missing deck: exit 2" "[[ $? -eq 2 ]] && grep -q deck <<< \"\$err\""
check "nothing written by the failures" "[[ ! -e c ]]"

"$ejecta" run dres-3cm --cell-size 10 --set end_time_s=0.0001 --set early.cells_per_charge_height=8 --quiet --no-plot --out d > /dev/null 2> d.err; rc=$?
check "a case without a target runs ($(tail -1 d.err))" "[[ $rc -eq 0 ]] && [[ -s d/history.csv ]]"

# A run folder is one unit. b (a restart) lists in fields.pvd only snapshots it holds (copied from a).
check "restart: every snapshot fields.pvd lists is in the folder" "grep -o 'fields/field_[0-9]*.vtr' b/fields.pvd | while read f; do [[ -s b/\$f ]] || exit 1; done"
# An interrupted rerun leaves the previous complete folder as it was...
cp a/summary.json a-summary.json
# (to 50 ms: about 10 s alone, so that it is still running when killed; to 10 ms it took 2.7 s since
# solver revision 15's longer steps and finished before the kill)
"$ejecta" run "${common[@]}" --set end_time_s=0.05 --out a > /dev/null 2>&1 &
pid=$!
sleep 4
kill -9 $pid 2> /dev/null
wait $pid 2> /dev/null
check "a killed rerun leaves the old folder intact" "cmp -s a/summary.json a-summary.json && [[ -s a/checkpoint.bin && -s a/fields/field_0000.vtr ]]"
# ...and a finished rerun replaces it whole: no stale checkpoint or snapshot of the earlier run,
# and the killed run's staging folder is cleared
"$ejecta" run "${common[@]}" --set 'output.field_times_s=[]' --out a --no-plot > /dev/null 2> a2.err; rc=$?
check "a rerun replaces the folder whole ($(tail -1 a2.err))" "[[ $rc -eq 0 && -s a/summary.json && ! -e a/checkpoint.bin && ! -e a/fields/field_0000.vtr && ! -e a/plots.png ]]"
check "no staging folders left" "[[ -z \$(ls -A | grep staging) ]]"
# A scheduler's SIGTERM (or Ctrl-C's SIGINT): the run stops at its next step, exits 128 + the signal,
# and removes what it had staged; the previous folder stays as it was. (A script's background job
# starts with SIGINT ignored, and a run keeps ignoring what it was started ignoring: TERM here.)
cp a/summary.json a-summary.json
"$ejecta" run "${common[@]}" --set end_time_s=0.05 --out a > /dev/null 2> int.err &
pid=$!
sleep 4
kill -TERM $pid 2> /dev/null
wait $pid
rc=$?
check "SIGTERM: exit 143 ($(tail -1 int.err)), nothing staged left, the old folder intact" \
  "[[ $rc -eq 143 ]] && [[ -z \$(ls -A | grep staging) ]] && cmp -s a/summary.json a-summary.json"
# Periodic checkpoints land no step: the history of a run without them. A signal then writes one
# more and keeps the staging folder; the restart gives the uninterrupted run's history.
long=(emi-flat-7 --cell-size 40 --set early.cells_per_charge_height=8 --set end_time_s=0.005 --no-plot --quiet)
"$ejecta" run "${long[@]}" --out ref > /dev/null 2>&1
"$ejecta" run "${long[@]}" --checkpoint-every 0.0003 --out pc > /dev/null 2> pc.err; rc=$?
check "--checkpoint-every: exit 0, checkpoints written ($(grep -c 'wrote checkpoint' pc.err)), the history of the run without them" \
  "[[ $rc -eq 0 ]] && [[ \$(grep -c 'wrote checkpoint' pc.err) -ge 2 ]] && cmp -s ref/history.csv pc/history.csv && [[ -s pc/checkpoint.bin ]]"
"$ejecta" run "${long[@]}" --checkpoint-every 0.0003 --out sig > /dev/null 2> sig.err &
pid=$!
for _ in $(seq 300); do grep -q 'wrote checkpoint' sig.err && break; sleep 0.05; done
kill -TERM $pid 2> /dev/null
wait $pid
rc=$?
ck=$(ls -d .sig.staging-*/checkpoint.bin 2> /dev/null | head -1)
check "--checkpoint-every: a signal writes a checkpoint ($(tail -1 sig.err)), exit 143, its staging folder kept" \
  "[[ $rc -eq 143 && -s '$ck' ]] && grep -q 'kept .*sig.staging' sig.err"
"$ejecta" run "${long[@]}" --restart "$ck" --out sig > /dev/null 2>&1; rc=$?
check "...its restart gives the uninterrupted run's history; the staging folder goes" \
  "[[ $rc -eq 0 ]] && cmp -s ref/history.csv sig/history.csv && [[ -z \$(ls -A | grep staging) ]]"
err=$("$ejecta" run "${long[@]}" --checkpoint-every 1 --checkpoint-at 0.001 --out both 2>&1 >/dev/null)
check "--checkpoint-every with --checkpoint-at: exit 2" "[[ $? -eq 2 ]] && grep -q 'not both' <<< \"\$err\" && [[ ! -e both ]]"
# Under nohup a hang-up is ignored, as nohup asks: the run goes on to its end.
nohup "$ejecta" run "${common[@]}" --set end_time_s=0.002 --no-plot --out hup > /dev/null 2> hup.err &
pid=$!
sleep 2
kill -HUP $pid 2> /dev/null
wait $pid
rc=$?
check "nohup: SIGHUP ignored, the run ends well (rc $rc)" "[[ $rc -eq 0 ]] && [[ -s hup/summary.json ]]"
err=$("$ejecta" run "${common[@]}" --set end_time_s=0.000001 --out c 2>&1 >/dev/null)
check "an end time within the early time: exit 2 naming end_time_s, nothing written" "[[ $? -eq 2 ]] && grep -q 'end_time_s.*early time' <<< \"\$err\" && [[ ! -e c ]]"
err=$("$ejecta" run "${common[@]}" --set 'output.gauges_m=[[0.0, 0.13]]' --out c 2>&1 >/dev/null)
check "a gauge in the plate: exit 2 naming output.gauges_m, nothing written" "[[ $? -eq 2 ]] && grep -q 'output.gauges_m.*target' <<< \"\$err\" && [[ ! -e c ]]"
err=$("$ejecta" run "${common[@]}" --set ' end_time_s = 0.0002 ' --set 'title = spaced title ' --no-plot --out spaced 2>&1 >/dev/null)
check "--set 'KEY = VALUE' with spaces, as TOML writes it" "[[ $? -eq 0 ]] && grep -q '\"end_time_s\": 0.0002' spaced/summary.json && grep -q '\"title\": \"spaced title\"' spaced/summary.json"

# ejecta sweep: a full factorial over one deck
"$ejecta" sweep emi-flat-7 --cell-size 25 --set end_time_s=0.0003 --set early.cells_per_charge_height=8 --vary target.standoff_m=0,0.05 --out s > s.txt 2> s.err; rc=$?
check "sweep exits 0 ($(tail -1 s.err))" "[[ $rc -eq 0 ]]"
check "sweep.csv has both cases" "[[ \$(wc -l < s/sweep.csv) -eq 3 ]] && [[ -s s/sweep.json && -s s/sweep.png ]]"
err=$("$ejecta" sweep emi-flat-7 --vary target.nonsense=1,2 --out t 2>&1 >/dev/null)
check "sweep: bad key exits 2 naming it, nothing written" "[[ $? -eq 2 ]] && grep -q target.nonsense <<< \"\$err\" && [[ ! -e t ]]"
sw=(emi-flat-7 --cell-size 40 --set early.cells_per_charge_height=8)
# a list value: its commas are its own; the CSV quotes it
"$ejecta" sweep "${sw[@]}" --set end_time_s=0.0003 --vary 'output.gauges_m=[[0.0, -0.01]],[[0.1, -0.01], [0.2, -0.01]]' --no-plot --out l > /dev/null 2> l.err; rc=$?
check "sweep: list values split at the top level only, quoted in sweep.csv ($(tail -1 l.err))" \
  "[[ $rc -eq 0 ]] && grep -q '^1,\"\[\[0.1, -0.01\], \[0.2, -0.01\]\]\",' l/sweep.csv && [[ \$(head -1 l/case_001/gauges.csv | tr ',' '\n' | wc -l) -eq 3 ]]"
# every case's geometry checked before the first runs: a gauge in the plate in the second case
err=$("$ejecta" sweep "${sw[@]}" --set end_time_s=0.0003 --vary 'output.gauges_m=[[0.1, -0.01]],[[0.1, 0.13]]' --out gg 2>&1 >/dev/null)
check "sweep: a case's geometry refused before any runs, exit 2 naming the field and the case" \
  "[[ $? -eq 2 ]] && grep -q 'output.gauges_m.*case 1: output.gauges_m=' <<< \"\$err\" && [[ ! -e gg ]]"
err=$("$ejecta" sweep emi-flat-7 --vary cfl=0.3,0.4 --set cfl=0.2 --out gg 2>&1 >/dev/null)
check "sweep: a key both set and varied, exit 2" "[[ $? -eq 2 ]] && grep -q 'cfl is both set and varied' <<< \"\$err\" && [[ ! -e gg ]]"
mkdir stranger && touch stranger/notes.txt
err=$("$ejecta" sweep emi-flat-7 --vary cfl=0.3 --out stranger 2>&1 >/dev/null)
check "sweep: a folder of other files refused, exit 2" "[[ $? -eq 2 ]] && grep -q 'not an ejecta sweep folder' <<< \"\$err\" && [[ \$(ls stranger) == notes.txt ]]"
# interrupted between cases' steps: what finished stays in the index, --reuse continues
"$ejecta" sweep "${sw[@]}" --set end_time_s=0.003 --vary target.standoff_m=0,0.05,0.1 --no-plot --out si > /dev/null 2> si.err &
pid=$!
for _ in $(seq 300); do grep -q 'case 2/3' si.err && break; sleep 0.1; done
kill -TERM $pid 2> /dev/null
wait $pid
rc=$?
check "sweep: SIGTERM exits 143, the index says interrupted with case 0 done" \
  "[[ $rc -eq 143 ]] && grep -q '\"status\": \"interrupted\"' si/sweep.json && grep -q ',done$' si/sweep.csv && grep -q '^1,.*,interrupted$' si/sweep.csv && grep -q '^2,.*,not run$' si/sweep.csv && [[ -z \$(ls -A si | grep staging) ]]"
"$ejecta" sweep "${sw[@]}" --set end_time_s=0.003 --vary target.standoff_m=0,0.05,0.1 --no-plot --out si --reuse > i2.txt 2> i2.err; rc=$?
check "sweep --reuse continues: case 0 reused, the others run ($(tail -1 i2.err))" \
  "[[ $rc -eq 0 ]] && [[ \$(grep -c ',reused$' si/sweep.csv) -eq 1 && \$(grep -c ',done$' si/sweep.csv) -eq 2 ]] && grep -q '\"status\": \"complete\"' si/sweep.json"
# with --checkpoint-every a case stopped by a signal continues from its checkpoint under --reuse,
# into the history of the case run whole
"$ejecta" sweep "${sw[@]}" --set end_time_s=0.006 --vary target.standoff_m=0.05 --no-plot --out sr > /dev/null 2>&1
"$ejecta" sweep "${sw[@]}" --set end_time_s=0.006 --vary target.standoff_m=0.05 --no-plot --checkpoint-every 0.0003 --out sc > /dev/null 2> sc.err &
pid=$!
for _ in $(seq 300); do grep -q 'wrote checkpoint' sc.err && break; sleep 0.05; done
kill -TERM $pid 2> /dev/null
wait $pid
rc=$?
"$ejecta" sweep "${sw[@]}" --set end_time_s=0.006 --vary target.standoff_m=0.05 --no-plot --out sc --reuse > /dev/null 2> sc2.err
check "sweep --checkpoint-every: a signal mid-case (rc $rc), --reuse continues it from its checkpoint into the whole run's history" \
  "[[ $rc -eq 143 ]] && grep -q 'sweep: case 0: continues from' sc2.err && cmp -s sr/case_000/history.csv sc/case_000/history.csv && [[ -z \$(ls -A sc | grep staging) ]]"
# a case that fails as it runs is recorded; the others run; the exit code is the failure's
rm -r si/case_002 && mkdir si/case_002 && touch si/case_002/stray
"$ejecta" sweep "${sw[@]}" --set end_time_s=0.003 --vary target.standoff_m=0,0.05,0.1 --no-plot --out si --reuse > /dev/null 2> f.err; rc=$?
check "sweep: a failed case recorded, the rest kept, exit 2 ($(tail -1 f.err))" \
  "[[ $rc -eq 2 ]] && grep -q '^2,.*,failed$' si/sweep.csv && grep -q 'not an ejecta run folder' si/sweep.json && [[ \$(grep -c ',reused$' si/sweep.csv) -eq 2 ]]"
# a smaller study into the same folder: the larger one's case folders go
rm -r si/case_002
"$ejecta" sweep "${sw[@]}" --set end_time_s=0.003 --vary target.standoff_m=0,0.05,0.1 --no-plot --out si --reuse > /dev/null 2>&1
# ... and the staging folder an interrupted extra case left (its process gone), but not a live run's
sh -c 'exit 0' & dead=$!
wait $dead
mkdir -p "si/.case_002.staging-$dead" "si/.case_003.staging-$$"
touch "si/.case_002.staging-$dead/checkpoint.bin"
"$ejecta" sweep "${sw[@]}" --set end_time_s=0.003 --vary target.standoff_m=0,0.05 --no-plot --out si --reuse > /dev/null 2>&1; rc=$?
check "sweep: an earlier study's extra case folders removed, and a dead extra case's staging folder" \
  "[[ $rc -eq 0 ]] && [[ \$(ls si | tr '\n' ' ') == 'case_000 case_001 sweep.csv sweep.json ' ]] && [[ ! -e si/.case_002.staging-$dead && -d si/.case_003.staging-$$ ]]"
rm -r "si/.case_003.staging-$$"

finish
