#!/bin/bash
# Issue 32's 16-core figures, on a machine with many cores and none of our
# Debian packages (a cluster node): a portable build packed by
# ../shared/tools/pack-portable.sh into .portable (its bin/xdyna, libraries
# and Open MPI), decks made there by tools/gen_decks.py. Not a test and not
# CI's: the figures go in the closing notes and doc/performance.md.
#   source .portable/env.sh; bash bench/device_scaling.sh [outdir]
# (here, a trial: XDYNA=bin/xdyna TUBES="2 2" CYCLES=20 PLATE="40 30" RANKS="1 2"
#  THREADS=2 PYTHON=/usr/bin/python3 bash bench/device_scaling.sh /tmp/scal)
# 1. the 10 x 10 array of crushing tubes (120,000 shells, whole-model
#    single-surface contact), 300 cycles, on 1, 2, 4, 8 and 16 ranks of one
#    thread, on one rank of 16 threads (and ranks x threads, HYBRID): wall
#    time, the time loop's,
#    its MPI phases' shares, peak memory per rank;
# 2. the 500 x 500 plate (250,000 shells, NIP 5), 20 cycles, on 1, 2, 4, 8
#    and 16 ranks: peak memory per rank, every nodal and element array a
#    rank holds, the nodes on the cuts and the halo's bytes a cycle;
# 3. the same plate with a whole-model single-surface contact (the issue's
#    "250,000-shell plate with contact", every node a slave), 20 cycles, on
#    1 and 16 ranks (PLATE_CONTACT_RANKS): peak memory per rank.
set -e
out=${1:-${OUT:-/tmp}/scaling}
mkdir -p $out
X=${XDYNA:-$PWD/.portable/bin/xdyna}
PY=${PYTHON:-python3}
$PY tools/gen_decks.py --bench-tubes ${TUBES:-10 10} $out/tubes.k --cycles ${CYCLES:-300} > /dev/null
$PY tools/gen_decks.py --bench-shells ${PLATE:-500 500} $out/plate.k --cycles 20 > /dev/null
$PY tools/gen_decks.py --bench-shells ${PLATE:-500 500} $out/plate_contact.k --cycles 20 --contact > /dev/null
echo "$(nproc) cores: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
one() {  # deck ranks threads tag
    local d=$out/$4
    local t0=$(date +%s%N)
    if [ "$2" -eq 1 ]; then
        OMP_NUM_THREADS=$3 $X i=$1 outdir=$d > $d.log 2>&1 < /dev/null
    elif [ "$3" -gt 1 ]; then
        mpirun --allow-run-as-root --oversubscribe --map-by slot:PE=$3 --bind-to core -np $2 -x OMP_NUM_THREADS=$3 \
            -x OMP_PROC_BIND=close -x OMP_PLACES=cores $X i=$1 outdir=$d > $d.log 2>&1 < /dev/null
    else
        mpirun --allow-run-as-root --oversubscribe --bind-to core -np $2 -x OMP_NUM_THREADS=$3 $X i=$1 outdir=$d \
            > $d.log 2>&1 < /dev/null
    fi
    local t1=$(date +%s%N)
    awk -v tag=$4 -v t0=$t0 -v t1=$t1 '
        /^ +total +[0-9.]+$/ {loop = $NF}
        /time per zone cycle/ {ns = $NF}
        /MPI halo exchange/ {halo = $5}
        /MPI contact exchange/ {ghost = $5}
        /MPI wait/ {wait = $5}
        /peak memory \(VmHWM\)/ {mem = sprintf("%.0f", $(NF - 1))}
        /peak memory per rank/ {mem = sprintf("%.0f-%.0f", $7, $12)}
        /nodal and element arrays \.\./ {arr = sprintf("%.1f", $(NF - 1))}
        /nodal and element arrays per rank/ {arr = sprintf("%.1f-%.1f", $8, $13)}
        /nodes on rank boundaries/ {s = $0; sub(/.*nodes on rank boundaries /, "", s); split(s, a, " "); cut = a[1]}
        /exchange a cycle, all ranks:/ {u = $0; sub(/.*all ranks: /, "", u); split(u, c, " "); p2p = c[1]}
        /nodes numbered per rank/ {loc = "local"}
        /every node on every rank/ {loc = "whole"}
        END {wall = (t1 - t0) / 1e9; printf "%-14s %8.2f %8s %8s %7s %7s %7s %14s %14s %7s %11s %6s\n", tag, wall, loop, ns, halo, ghost, wait, \
                    mem, arr, cut, p2p, loc}' $d/d3hsp
}
printf '%-14s %8s %8s %8s %7s %7s %7s %14s %14s %7s %11s %6s\n' run "wall s" "loop s" "ns/el-c" "halo%" "cont%" \
    "wait%" "peak MB/rank" "arrays MB/rk" "cut" "halo B/cyc" nodes
for r in ${RANKS:-1 2 4 8 16}; do one $out/tubes.k $r 1 tubes_r$r; done
one $out/tubes.k 1 ${THREADS:-16} tubes_t${THREADS:-16}
# ranks x threads (HYBRID="4x4 2x8": 4 ranks of 4 threads, 2 of 8)
for h in ${HYBRID:-}; do one $out/tubes.k ${h%x*} ${h#*x} tubes_$h; done
for r in ${RANKS:-1 2 4 8 16}; do one $out/plate.k $r 1 plate_r$r; done
for r in ${PLATE_CONTACT_RANKS:-1 16}; do one $out/plate_contact.k $r 1 plate_contact_r$r; done
