#!/usr/bin/env bash
# `ejecta run` on MPI ranks (docs/solver.md, domain decomposition): the same deck on 1 process and
# on 2 and 3 ranks prints the same impulse and writes the same history, gauges and surface profiles
# byte for byte (2D axisymmetric and the 3D V-plate); a checkpoint written on 2 ranks restarts on 1
# and on 3 into the uninterrupted run's history; each rank writes its piece of a field snapshot and
# the pieces joined are the one process's snapshot value for value; bad input on ranks exits 2,
# said once, and like an interrupt the ranks agreed on ends them without an abort.
# Usage: test_mpi_run.sh EJECTA MPIEXEC
set -uo pipefail
ejecta=$(realpath "$1"); mpiexec=$2; pieces_match=$(realpath "$(dirname "$0")/vtr_pieces_match.py")
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT; cd "$work"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1 OMPI_MCA_rmaps_base_oversubscribe=1
fails=0
check() {   # name, then a command that must succeed
  if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1"; fails=$((fails + 1)); fi
}
ranks() { local n=$1; shift; "$mpiexec" -np "$n" --oversubscribe "$ejecta" "$@"; }
same() {   # folders a and b: the printed impulse, the run's tables and summary.json's results are the same
  cmp -s "$1/history.csv" "$2/history.csv" && cmp -s "$1/gauges.csv" "$2/gauges.csv" && cmp -s "$1/surface_profiles.csv" "$2/surface_profiles.csv" \
    && [[ "$(grep impulse "$1.out")" == "$(grep impulse "$2.out")" ]] && [[ -n "$(grep impulse "$1.out")" ]] \
    && python3 -c "import json,sys; a,b=(json.load(open(f+'/summary.json')) for f in sys.argv[1:]); sys.exit(a['result']!=b['result'] or a['totals']!=b['totals'])" "$1" "$2"
}
flat=(run emi-flat-22 --cell-size 40 --set end_time_s=0.001 --set 'output.field_times_s=[0.0005,0.001]' --no-plot --quiet)
"$ejecta" "${flat[@]}" --out f1 > f1.out 2>/dev/null
ranks 2 "${flat[@]}" --out f2 > f2.out 2>/dev/null
ranks 3 "${flat[@]}" --out f3 > f3.out 2>/dev/null
check "2D: 2 ranks as 1 process ($(grep impulse f1.out | xargs))" "same f1 f2"
check "2D: 3 ranks as 1 process" "same f1 f3"
check "2D: summary.json records the ranks" "grep -q '\"ranks\": 3' f3/summary.json"
check "2D fields: 2 and 3 pieces joined are the one process's snapshot ($(python3 "$pieces_match" f1/fields/field_0001.vtr f3/fields/field_0001.pvtr))" \
  "for r in 2 3; do for i in 0 1; do python3 '$pieces_match' f1/fields/field_000\$i.vtr f\$r/fields/field_000\$i.pvtr >/dev/null || exit 1; done; done"
check "fields.pvd lists each snapshot's index at its time" "grep -q 'timestep=\"0.001\" file=\"fields/field_0001.pvtr\"' f2/fields.pvd && [[ \$(ls f2/fields | wc -l) -eq 6 ]]"
check "ranks other than 0 write nothing beside the run folders ($(ls | tr '\n' ' '))" "[[ \$(ls | grep -cv -e '^f[123]\$' -e '^f[123].out\$') -eq 0 ]]"
v=(run emi-v120-7 --cell-size 60 --set end_time_s=0.0005 --set 'output.field_times_s=[0.0005]' --no-plot --quiet)
"$ejecta" "${v[@]}" --out v1 > v1.out 2>/dev/null
ranks 2 "${v[@]}" --out v2 > v2.out 2>/dev/null
check "3D V-plate: 2 ranks as 1 process ($(grep impulse v1.out | xargs))" "same v1 v2"
check "3D fields: 2 pieces joined are the one process's snapshot" "python3 '$pieces_match' v1/fields/field_0000.vtr v2/fields/field_0000.pvtr >/dev/null"
cover=(run field-cover7-2.5cm --cell-size 40 --set 'output.field_times_s=[0.0002,0.0008]' --no-plot --quiet)
"$ejecta" "${cover[@]}" --set end_time_s=0.001 --out u > u.out 2>/dev/null
ranks 2 "${cover[@]}" --set end_time_s=0.0005 --checkpoint-at 0.00025 --out c > /dev/null 2>&1
"$ejecta" "${cover[@]}" --set end_time_s=0.001 --restart c/checkpoint.bin --out r1 > r1.out 2>/dev/null
ranks 3 "${cover[@]}" --set end_time_s=0.001 --restart c/checkpoint.bin --out r3 > r3.out 2>/dev/null
check "a checkpoint of 2 ranks restarts on 1 process as the uninterrupted run" "cmp -s u/history.csv r1/history.csv"
check "...and on 3 ranks" "cmp -s u/history.csv r3/history.csv"
check "...on 1 process: its folder holds the 2 ranks' snapshot (index and pieces) and its own .vtr, each listed" \
  "grep -q 'fields/field_0000.pvtr' r1/fields.pvd && grep -q 'fields/field_0001.vtr' r1/fields.pvd && [[ -s r1/fields/field_0000_p0001.vtr && -s r1/fields/field_0001.vtr ]]"
check "...on 3 ranks: its folder holds the 2 ranks' snapshots before the checkpoint and its own after, each listed" \
  "grep -o 'fields/field_[0-9]*.pvtr' r3/fields.pvd | while read f; do [[ -s r3/\$f ]] || exit 1; for p in \$(grep -o 'Source=\"[^\"]*' r3/\$f | cut -d'\"' -f2); do [[ -s r3/fields/\$p ]] || exit 1; done; done \
   && [[ \$(grep -c pvtr r3/fields.pvd) -ge 2 ]]"
# A rank that cannot write its piece (here a file size limit on rank 1 alone): every rank stops, the
# cause said once with the rank that met it, no run folder and nothing staged left.
cat > limited.sh <<'EOF2'
#!/usr/bin/env bash
trap '' XFSZ; ulimit -f 2; exec "$@"
EOF2
chmod +x limited.sh
err=$("$mpiexec" --oversubscribe -np 1 "$ejecta" "${flat[@]}" --out nospace : -np 1 ./limited.sh "$ejecta" "${flat[@]}" --out nospace 2>&1 >/dev/null); rc=$?
check "a piece that cannot be written: exit 1, the cause said once, nothing left ($(grep -m1 'ejecta:' <<< "$err"))" \
  "[[ $rc -eq 1 ]] && [[ \$(grep -c 'could not write the pieces' <<< \"\$err\") -eq 1 ]] && grep -q 'rank 1: ' <<< \"\$err\" && [[ ! -e nospace ]] && [[ -z \$(ls -A | grep staging) ]]"
err=$(ranks 2 run --set mesh.cell_size_m=-1 --out bad 2>&1 >/dev/null); rc=$?
check "bad input on ranks: exit 2, said once, every rank ends without an abort" "[[ $rc -eq 2 ]] && [[ \$(grep -c 'mesh.cell_size_m' <<< \"\$err\") -eq 1 ]] && [[ ! -e bad ]] && ! grep -q -e MPI_ABORT -e "ending every rank" <<< \"\$err\""
# Bad input on one rank alone (another deck value there): the others wait in the run's collectives,
# so after the wait for agreement that rank ends them all, saying its error with its rank.
t0=$SECONDS
err=$(timeout 120 "$mpiexec" --oversubscribe -np 1 "$ejecta" "${flat[@]}" --out alone : -np 1 "$ejecta" "${flat[@]}" --set end_time_s=-1 --out alone 2>&1 >/dev/null); rc=$?
waited=$((SECONDS - t0))
check "bad input on one rank alone: after the 10 s wait every rank is ended by an abort, the error said with its rank (rc $rc, ${waited} s)" \
  "[[ $rc -eq 2 && $waited -ge 10 ]] && grep -q 'rank 1: the other ranks did not come to the end within 10 s: ending every rank (MPI_Abort)' <<< \"\$err\" && grep -q 'rank 1: end_time_s' <<< \"\$err\" && [[ ! -e alone ]]"
# A signal on one rank that is not rank 0 stops every rank at the same step; with --checkpoint-every
# they write a checkpoint first, and a restart on 1 process gives the uninterrupted run's history.
long=(run emi-flat-22 --cell-size 40 --set end_time_s=0.02 --no-plot --quiet)
"$ejecta" "${long[@]}" --out l1 > l1.out 2>/dev/null
ranks 2 "${long[@]}" --checkpoint-every 10 --out l2 > /dev/null 2> l2.err &
pid=$!
for _ in $(seq 300); do grep -q 'MPI ranks' l2.err && break; sleep 0.1; done
sleep 0.5
for p in $(pgrep -f -- "--out l2"); do
  tr '\0' '\n' < /proc/"$p"/environ 2> /dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=1' && kill -TERM "$p"
done
wait $pid; rc=$?
ck=$(ls -d .l2.staging-*/checkpoint.bin 2> /dev/null | head -1)
check "SIGTERM to rank 1 alone: every rank stops at its step, rank 0 keeps the checkpoint ($(grep -m1 interrupted l2.err))" \
  "[[ -s '$ck' ]] && grep -q 'interrupted by signal 15' l2.err"
check "...the ranks agreed, so they end without an abort: exit 143, said once (rc $rc)" \
  "[[ $rc -eq 143 ]] && ! grep -q -e MPI_ABORT -e "ending every rank" l2.err && [[ \$(grep -c 'interrupted by signal' l2.err) -eq 1 ]]"
"$ejecta" "${long[@]}" --restart "$ck" --out l2 > /dev/null 2>&1
check "...restarted on 1 process: the uninterrupted run's history, no staging folder left" \
  "cmp -s l1/history.csv l2/history.csv && [[ -z \$(ls -A | grep staging) ]]"
err=$(ranks 2 run --bogus-option 2>&1 >/dev/null); rc=$?
check "an unknown option on ranks: exit 2, said once, no abort" "[[ $rc -eq 2 ]] && [[ \$(grep -c 'bogus-option' <<< \"\$err\") -eq 1 ]] && ! grep -q -e MPI_ABORT -e "ending every rank" <<< \"\$err\""
err=$(ranks 2 soil --json 2>&1 >/dev/null); rc=$?
check "only run runs on ranks: exit 2, no abort" "[[ $rc -eq 2 ]] && grep -q 'only \`ejecta run\`' <<< \"\$err\" && ! grep -q -e MPI_ABORT -e "ending every rank" <<< \"\$err\""
echo "$fails failed"
exit $((fails > 0))
