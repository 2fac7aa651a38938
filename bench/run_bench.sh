#!/bin/sh
# make bench: nanoseconds per element-cycle on one core for a generated
# block of hexahedra (default 100 x 50 x 20 = 100,000 elements), median of
# three runs, with the phase split from d3hsp and the peak memory.
#   BENCH_SIZE="100 50 20" BENCH_CYCLES=200 BENCH_RUNS=3 sh bench/run_bench.sh
set -e
size=${BENCH_SIZE:-"100 50 20"}
cycles=${BENCH_CYCLES:-200}
runs=${BENCH_RUNS:-3}
dir=build/bench
mkdir -p $dir
set -- $size
nel=$(($1 * $2 * $3))
deck=$dir/block_$1x$2x$3.k
/usr/bin/python3 tools/gen_decks.py --bench $1 $2 $3 $deck --cycles $cycles
echo "bench: $nel hexahedra, $cycles cycles, 1 thread, $runs runs ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'))"
: > $dir/ns.txt
i=1
while [ $i -le $runs ]; do
    out=$dir/run$i
    rm -rf $out
    OMP_NUM_THREADS=1 /usr/bin/time -f "%M" -o $dir/mem$i.txt ./bin/xdyna i=$deck outdir=$out > /dev/null
    ns=$(grep 'time per zone cycle' $out/d3hsp | awk '{print $NF}')
    el=$(grep 'element processing' $out/d3hsp | awk -v n=$nel -v c=$cycles '{printf "%.1f", $3 / (n * c) * 1e9}')
    as=$(grep 'force assembly' $out/d3hsp | awk -v n=$nel -v c=$cycles '{printf "%.1f", $3 / (n * c) * 1e9}')
    ti=$(grep 'time integration' $out/d3hsp | awk -v n=$nel -v c=$cycles '{printf "%.1f", $3 / (n * c) * 1e9}')
    echo "  run $i: $ns ns per element-cycle (elements $el, assembly $as, integration $ti), peak memory $(cat $dir/mem$i.txt) kB"
    echo "$ns" >> $dir/ns.txt
    i=$((i + 1))
done
med=$(sort -n $dir/ns.txt | awk '{a[NR]=$1} END {print a[int((NR + 1) / 2)]}')
mem=$(cat $dir/mem1.txt)
echo "bench: median $med ns per element-cycle (hex8 one-point, viscous hourglass, elastic), $((mem * 1024 / nel)) bytes per element peak"

# shells: 400 x 250 = 100,000 Belytschko-Tsay shells, *MAT_024, 5 points
sdeck=$dir/plate_400x250.k
scycles=${BENCH_SHELL_CYCLES:-100}
/usr/bin/python3 tools/gen_decks.py --bench-shells 400 250 $sdeck --cycles $scycles
echo "bench: 100000 Belytschko-Tsay shells (*MAT_024, NIP 5, yielding), $scycles cycles, 1 thread, $runs runs"
: > $dir/ns_shell.txt
i=1
while [ $i -le $runs ]; do
    out=$dir/shell$i
    rm -rf $out
    OMP_NUM_THREADS=1 ./bin/xdyna i=$sdeck outdir=$out > /dev/null
    ns=$(grep 'time per zone cycle' $out/d3hsp | awk '{print $NF}')
    echo "  run $i: $ns ns per element-cycle"
    echo "$ns" >> $dir/ns_shell.txt
    i=$((i + 1))
done
med=$(sort -n $dir/ns_shell.txt | awk '{a[NR]=$1} END {print a[int((NR + 1) / 2)]}')
echo "bench: shells median $med ns per element-cycle"

# states: the same plate with 20 states over the run (the default output:
# the d3plot family); their cost against the median above (aim: at most 10%
# of the run)
tend=$(/usr/bin/python3 -c "import h5py; print(h5py.File('$dir/shell1/thist.h5')['glstat/time'][-1])")
sdt=$(/usr/bin/python3 -c "print($tend / 20 * 0.999)")
/usr/bin/python3 tools/gen_decks.py --bench-shells 400 250 $dir/plate_states.k --cycles $scycles --states-dt $sdt
: > $dir/ns_states.txt
i=1
while [ $i -le $runs ]; do
    out=$dir/states$i
    rm -rf $out
    OMP_NUM_THREADS=1 ./bin/xdyna i=$dir/plate_states.k outdir=$out > /dev/null
    grep 'time per zone cycle' $out/d3hsp | awk '{print $NF}' >> $dir/ns_states.txt
    i=$((i + 1))
done
nst=$(sed -n 's/^ states: \([0-9]*\) written.*/\1/p' $dir/states1/d3hsp)
smed=$(sort -n $dir/ns_states.txt | awk '{a[NR]=$1} END {print a[int((NR + 1) / 2)]}')
echo "bench: shells with $nst states: median $smed ns per element-cycle, states cost $(awk -v a=$smed -v b=$med 'BEGIN {printf "%.1f", 100 * (a - b) / b}')% of the run ($(cat $dir/states1/d3plot* | wc -c | awk '{printf "%.0f", $1 / 1048576}') MB of states)"

# one row per run: ns per element-cycle over all elements (rigid ones
# included, as the peer counts them), from the time loop's wall time in
# d3hsp, split by phase; contact share; peak memory per element
phase_row() {  # label d3hsp nelem memkB
    awk -v label="$1" -v n=$3 -v mem=$4 '
        /element processing/ {el = $3}
        /force assembly/ {as = $3}
        /time integration/ {ti = $3}
        /rigid bodies/ {rb = $3}
        /contact global search/ {gs = $4}
        /contact local search/ {ls = $4}
        /contact enforcement/ {en = $3}
        /output  / {ou = $2}
        /contact share/ {share = $(NF-1)}
        /cycles \.\.\./ {c = $NF}
        END {f = 1e9 / (n * c); loop = el + as + ti + rb + gs + ls + en + ou
             printf "  %s: %.0f ns per element-cycle (elements %.0f, assembly %.0f, integration %.0f, rigid %.0f, global search %.0f, local search %.0f, enforcement %.0f); contact %s%%; %d cycles; %.1f kB per element\n", label, loop * f, el * f, as * f, ti * f, rb * f, gs * f, ls * f, en * f, share, c, mem / n}' $2
}

# the tube crushed by a coarse rigid plate (1,200 tube shells of 5 mm, a
# rigid plate of 484 shells of 10 mm, whole-model single-surface contact,
# 10 m/s, 12 ms: 120 of the 150 mm crushed), one thread, three runs
tpdeck=$dir/tube_plate.k
/usr/bin/python3 tools/gen_decks.py --bench-tube-plate $tpdeck
echo "bench: square tube crushed by a coarse rigid plate, 1684 shells, whole crush (12 ms), 1 thread, $runs runs"
: > $dir/ns_tp.txt
i=1
while [ $i -le $runs ]; do
    out=$dir/tube_plate$i
    rm -rf $out
    OMP_NUM_THREADS=1 /usr/bin/time -f "%M" -o $dir/mem_tp$i.txt ./bin/xdyna i=$tpdeck outdir=$out > /dev/null
    phase_row "run $i" $out/d3hsp 1684 $(cat $dir/mem_tp$i.txt) | tee -a $dir/ns_tp.txt
    i=$((i + 1))
done
awk '{for (k = 1; k <= NF; k++) if ($k == "ns") {print $(k - 1)}}' $dir/ns_tp.txt | sort -n | \
    awk '{a[NR]=$1} END {print "bench: tube under a coarse plate: median " a[int((NR + 1) / 2)] " ns per element-cycle"}'

# the same deck with the 32-bit build (make PRECISION=single), one run
out=$dir/tube_plate_single
rm -rf $out
OMP_NUM_THREADS=1 /usr/bin/time -f "%M" -o $dir/mem_tps.txt ./bin/xdyna_single i=$tpdeck outdir=$out > /dev/null
phase_row "32-bit build" $out/d3hsp 1684 $(cat $dir/mem_tps.txt)

# the paper's front frame (section 7.3, 2,354 shells, 30 ms), one run
out=$dir/front_frame
rm -rf $out
OMP_NUM_THREADS=1 /usr/bin/time -f "%M" -o $dir/mem_ff.txt ./bin/xdyna i=input_decks/paper/front_frame.k outdir=$out > /dev/null
phase_row "bench: the paper's front frame (2354 shells, 30 ms, 1 thread)" $out/d3hsp 2354 $(cat $dir/mem_ff.txt)

# global search alone (contact step 2) on crumpled sheets of 1e4, 1e5, 1e6
# surface nodes: the cost per slave node must stay flat (a linear search)
echo "bench: contact global search alone, crumpled sheet, 1 thread (median of repeats per size)"
# and the mixed-size cases against their uniform twins
OMP_NUM_THREADS=1 ./bin/search_bench | tee $dir/search.txt
awk '$1 == "crumpled" {n++; c[n] = $6} END {printf "bench: global search cost per slave grows %.2fx from 1e4 to 1e6 nodes\n", c[n] / c[1]}' $dir/search.txt

# whole-model single-surface contact: an array of crushing square tubes
# (1200 shells each), 3 x 3 = 10,800 shells (BENCH_TUBES="10 10" for
# 120,000), BENCH_TUBE_CYCLES cycles, one thread
tubes=${BENCH_TUBES:-"3 3"}
tcycles=${BENCH_TUBE_CYCLES:-1500}
set -- $tubes
tdeck=$dir/tubes_$1x$2.k
/usr/bin/python3 tools/gen_decks.py --bench-tubes $1 $2 $tdeck --cycles $tcycles
nsh=$(($1 * $2 * 1200))
out=$dir/tubes
rm -rf $out
OMP_NUM_THREADS=1 ./bin/xdyna i=$tdeck outdir=$out > /dev/null
echo "bench: $nsh shells in $1 x $2 crushing tubes, whole-model single-surface contact, $tcycles cycles, 1 thread"
awk -v n=$nsh -v c=$tcycles '
    /time per zone cycle/ {zone = $NF}
    /contact share/ {share = $(NF-1)}
    /element processing/ {el = $3}
    /contact global search/ {gs = $4}
    /contact local search/ {ls = $4}
    /contact enforcement/ {en = $3}
    END {f = 1e9 / (n * c)
         printf "bench: contact %.1f ns per element-cycle overall (elements %.1f, global search %.1f, local search %.1f, enforcement %.1f); contact share %s%%\n", zone, el * f, gs * f, ls * f, en * f, share}' $out/d3hsp

# threads: the shell plate and the tubes again with 2 threads (results are
# bitwise the same as with one; this machine has 2 cores)
out2=$dir/shell_t2
rm -rf $out2
OMP_NUM_THREADS=2 ./bin/xdyna i=$sdeck outdir=$out2 > /dev/null
ns2=$(grep 'time per zone cycle' $out2/d3hsp | awk '{print $NF}')
echo "bench: threads: shells $med ns per element-cycle on 1 thread (median), $ns2 on 2: speed-up $(awk -v a=$med -v b=$ns2 'BEGIN {printf "%.2f", a / b}')x"
out2=$dir/tubes_t2
rm -rf $out2
OMP_NUM_THREADS=2 ./bin/xdyna i=$tdeck outdir=$out2 > /dev/null
awk -v t1="$(grep '  total' $out/d3hsp | awk '{print $NF}')" '
    /  total/ {t2 = $NF}
    /element processing/ {el2 = $3}
    /contact local search/ {ls2 = $4}
    END {printf "bench: threads: tubes %.2f s on 1 thread, %.2f s on 2: speed-up %.2fx (elements %.2f s, local search %.2f s on 2)\n", t1, t2, t1 / t2, el2, ls2}' $out2/d3hsp

# ranks: the same two decks on 2 MPI ranks of one thread, with owned nodes
# (the motion bitwise the same as one rank's, the energies to rounding). The
# d3hsp of rank 0 splits the MPI time: the halo exchange (force slots of
# elements on the other rank, the velocities of the nodes the ranks share,
# and of the contact surfaces; every node gathered only for a state), the
# contact exchange (the contacts each rank's slaves found) and the wait at
# the cycle's first collective (the other rank's elements not done: load
# imbalance)
mpi="mpirun --allow-run-as-root --oversubscribe -np 2 -x OMP_NUM_THREADS=1"
out2=$dir/shell_r2
rm -rf $out2
OMP_NUM_THREADS=1 $mpi ./bin/xdyna i=$sdeck outdir=$out2 > /dev/null
awk -v med=$med -v n=100000 -v c=$scycles '
    /time per zone cycle/ {zone = $NF}
    /MPI halo exchange/ {halo = $4}
    /MPI wait/ {wait = $4}
    /  total/ {tot = $NF}
    END {printf "bench: ranks: shells %s ns per element-cycle on 1 rank (median), %s on 2: speed-up %.2fx; halo exchange %.1f%% of the run (%.0f us a cycle), wait %.1f%%\n", med, zone, med / zone, 100 * halo / tot, 1e6 * halo / c, 100 * wait / tot}' $out2/d3hsp
out2=$dir/tubes_r2
rm -rf $out2
OMP_NUM_THREADS=1 $mpi ./bin/xdyna i=$tdeck outdir=$out2 > /dev/null
awk -v t1="$(grep '  total' $out/d3hsp | awk '{print $NF}')" -v c=$tcycles '
    /  total/ {t2 = $NF}
    /MPI halo exchange/ {halo = $4}
    /MPI contact exchange/ {ghost = $4}
    /MPI wait/ {wait = $4}
    END {printf "bench: ranks: tubes %.2f s on 1 rank, %.2f s on 2: speed-up %.2fx; halo exchange %.1f%% (%.0f us a cycle), contact exchange %.1f%% (%.0f us a cycle), wait %.1f%%\n", t1, t2, t1 / t2, 100 * halo / t2, 1e6 * halo / c, 100 * ghost / t2, 1e6 * ghost / c, 100 * wait / t2}' $out2/d3hsp

# car6, the public car deck (../shared/public-decks, or XDYNA_PUBLIC_DECKS),
# unchanged, whole 0.2 s, one thread, BENCH_RUNS runs: wall time, cycles, ns
# per element-cycle by phase, peak memory; the median run's figures
public=${XDYNA_PUBLIC_DECKS:-../shared/public-decks}
if [ -f $public/car6_main.k ]; then
    cdir=$dir/car6
    rm -rf $cdir
    mkdir -p $cdir
    cp $public/*.k $cdir/
    echo "bench: car6 (car6_main.k unchanged, 2424 shells, 0.2 s), 1 thread, $runs runs"
    : > $dir/car6.txt
    i=1
    while [ $i -le $runs ]; do
        out=$cdir/run$i
        OMP_NUM_THREADS=1 /usr/bin/time -f "%M" -o $cdir/mem$i.txt ./bin/xdyna i=$cdir/car6_main.k outdir=$out > /dev/null
        awk -v mem=$(cat $cdir/mem$i.txt) -v n=2424 '
            /element processing/ {el = $3}
            /force assembly/ {as = $3}
            /time integration/ {ti = $3}
            /rigid walls/ {rw = $3}
            /contact global search/ {gs = $4}
            /contact local search/ {ls = $4}
            /contact enforcement/ {en = $3}
            /output  / {ou = $2}
            /  total/ {tot = $NF}
            /cycles \.\.\./ {c = $NF}
            END {f = 1e9 / (n * c)
                 printf "%.2f s wall, %d cycles, %.0f ns per element-cycle (elements %.0f, assembly %.0f, integration %.0f, walls %.0f, global search %.0f, local search %.0f, enforcement %.0f, output %.0f: %.1f%% of the run); peak memory %d kB\n", tot, c, tot * f, el * f, as * f, ti * f, rw * f, gs * f, ls * f, en * f, ou * f, 100 * ou / tot, mem}' \
            $out/d3hsp | tee -a $dir/car6.txt | sed "s/^/  run $i: /"
        i=$((i + 1))
    done
    sort -n $dir/car6.txt | awk '{a[NR]=$0} END {print "bench: car6 median: " a[int((NR + 1) / 2)]}'
    echo "bench: car6 peer (doc/performance.md): OpenRadioss 56.0 s, 31,160 cycles, one core of a 2-core AMD EPYC machine of this class"
else
    echo "bench: car6 SKIPPED: $public/car6_main.k is not here"
fi
