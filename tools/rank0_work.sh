#!/bin/bash
# Instructions rank 0 executes in an N-rank run, by phase (valgrind's
# callgrind on rank 0 alone; the other ranks run natively). A count does not
# depend on the cores or on the other ranks' speed, so a 2-core machine
# running 16 ranks oversubscribed measures what each rank's share of the
# work is: the serial run's instructions over rank 0's bound the speed-up
# N cores can give (the set-up every rank repeats, the per-cycle work that
# does not fall with the ranks).
#
# usage: tools/rank0_work.sh NRANKS DECK [OUTDIR]   (NRANKS 1: the serial run)
# needs valgrind (a developer's tool; not installed by make deps)
set -e
n=${1:?ranks}
deck=${2:?deck}
out=${3:-/tmp/rank0_work_$n}
here=$(cd "$(dirname "$0")/.." && pwd)
bin=$here/bin/xdyna
command -v valgrind > /dev/null || { echo "rank0_work: valgrind is not installed" >&2; exit 1; }
rm -rf "$out" && mkdir -p "$out"
export OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cg="valgrind --tool=callgrind --callgrind-out-file=$out/callgrind.out"
if [ "$n" = 1 ]; then
    $cg "$bin" i="$deck" outdir="$out" > "$out/log" 2>&1
else
    mpirun --oversubscribe -np 1 $cg "$bin" i="$deck" outdir="$out" : \
        -np $((n - 1)) "$bin" i="$deck" outdir="$out" > "$out/log" 2>&1
fi
callgrind_annotate --inclusive=yes "$out/callgrind.out" 2> /dev/null | awk -v n="$n" '
    /PROGRAM TOTALS/ { gsub(",", "", $1); total = $1 }
    function put(key, name) { if (!(key in seen)) { v = $1; gsub(",", "", v); seen[key] = v; order[++k] = key; label[key] = name } }
    /MOD_read_deck /             { put("read", "deck reading") }
    /MOD_build_domain /          { put("domain", "decomposition (build_domain)") }
    /MOD_build_contacts /        { put("contacts", "contact surfaces (build_contacts, every call)") }
    /MOD_initial_penetrations /  { put("initpen", "initial penetrations (with their build_contacts)") }
    /MOD_setup_run /             { put("setup", "elements and masses (setup_run, every call)") }
    /MOD_run_time_loop /         { put("loop", "time loop") }
    /MOD_element_phase /         { put("elem", "  element forces") }
    /MOD_contact_search /        { put("search", "  contact global search") }
    /MOD_contact_ghosts /        { put("ghosts", "  contact ghosts'"'"' lists") }
    END {
        printf "rank 0 of %d: %.3e instructions\n", n, total
        for (i = 1; i <= k; i++) printf "  %-52s %.3e\n", label[order[i]], seen[order[i]]
    }'
