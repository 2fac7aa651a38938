#!/bin/sh
# make bench-mpi (issue 32): the array of crushing tubes (tools/gen_decks.py
# --bench-tubes: 1,200 shells a tube, NIP 5, *MAT_024, whole-model
# single-surface contact) on 1, 2, 4 ... MPI ranks of one thread each: wall
# time of the time loop, ns per element-cycle, the MPI phases' shares
# (halo exchange, contact exchange, the wait for the slowest rank), the
# contact's share, the peak memory per rank (VmHWM, smallest and largest),
# the resident memory at the end (VmRSS) and the elements' state and force
# slots each rank holds (its own elements' alone), every nodal and element
# array a rank holds (d3hsp's 'nodal and element arrays'), the contact's arrays
# (d3hsp's 'contact arrays at the end'), rank 0's local search's
# gather between searches (surface nodes it moves, of all) and the share of
# the contact pairs listed that it applied (contact ghosts), the surface
# nodes rank 0 sent to the other ranks at a search (search_exchange) and
# the contacts' bytes exchanged a cycle over all ranks (each to its nodes'
# ranks: send_contacts)
# and the halo's bytes a cycle (with owned nodes: the halo point-to-point and
# the contact surfaces' velocities to every rank; replicated: the slots and
# every node's forces to every rank; and each rank's own halo nodes' share,
# from the decomposition table). Results are bitwise the same
# for any rank count (make check holds that); here the ranks share this
# machine's cores (oversubscribed beyond them): memory and bytes are
# figures, times are not scaling.
#   BENCH_MPI_TUBES="10 10" BENCH_MPI_CYCLES=100 BENCH_MPI_RANKS="1 2 4" sh bench/run_bench_mpi.sh
# (10 x 10 tubes: 120,000 shells; 29 x 29: 1,009,200, about 2.8 GB a rank;
# several sizes separated by commas, BENCH_MPI_TUBES="10 10,29 29")
set -e
sizes=${BENCH_MPI_TUBES:-10 10}
cycles=${BENCH_MPI_CYCLES:-100}
ranks=${BENCH_MPI_RANKS:-1 2 4}
dir=build/bench_mpi
mkdir -p $dir
echo "$sizes" | tr ',' '\n' | while read size; do
set -- $size
ntx=$1
nty=$2
deck=$dir/tubes_${ntx}x${nty}.k
/usr/bin/python3 tools/gen_decks.py --bench-tubes $ntx $nty $deck --cycles $cycles
nel=$((ntx * nty * 1200))
echo "bench-mpi: $ntx x $nty tubes, $nel shells, $cycles cycles, one thread a rank, $(nproc) cores here ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'))"
printf '%6s %9s %10s %8s %9s %8s %9s %17s %17s %12s %14s %14s %16s %16s %18s %9s %14s %14s\n' ranks "wall (s)" "ns/el-cyc" "halo %" "contact%" "wait %" "c.share" "peak MB/rank" "end MB/rank" "elem MB/rk" "arrays MB/rk" "contact MB/rk" "halo B/cycle" "own-node halo B" "srf gathered (r0)" "pairs %" "srf sent/srch" "contacts B/cyc"
for r in $ranks; do
    out=$dir/r${r}_${ntx}x${nty}
    rm -rf $out
    if [ "$r" -eq 1 ]; then
        OMP_NUM_THREADS=1 ./bin/xdyna i=$deck outdir=$out > /dev/null < /dev/null
    else
        mpirun --allow-run-as-root --oversubscribe -np $r -x OMP_NUM_THREADS=1 ./bin/xdyna i=$deck outdir=$out > /dev/null < /dev/null
    fi
    awk -v r=$r '
        /  total/ {tot = $NF}
        /time per zone cycle/ {ns = $NF}
        /MPI halo exchange/ {halo = $4}
        /MPI contact exchange/ {ghost = $4}
        /MPI wait/ {wait = $4}
        /contact share of the time loop/ {cs = $(NF - 1)}
        /peak memory \(VmHWM\)/ {mem = sprintf("%.0f", $(NF - 1))}
        /peak memory per rank/ {lo = $7; hi = $12; mem = sprintf("%.0f-%.0f", lo, hi)}
        /resident memory at the end \(VmRSS\) \.\./ {rss = sprintf("%.0f", $(NF - 1))}
        /resident memory at the end per rank/ {rss = sprintf("%.0f-%.0f", $9, $14)}
        /elements. state and force slots \(/ {el = sprintf("%.1f", $(NF - 1))}
        /elements. state and force slots per rank/ {el = sprintf("%.1f", $14)}
        /nodal and element arrays \.\./ {arr = sprintf("%.1f", $(NF - 1))}
        /nodal and element arrays per rank/ {arr = sprintf("%.1f-%.1f", $8, $13)}
        /contact arrays at the end \.\./ {con = sprintf("%.1f", $(NF - 1))}
        /contact arrays at the end per rank/ {con = sprintf("%.1f-%.1f", $9, $14)}
        /halo exchange a cycle:/ {
            s = $0; sub(/.*force slots \(/, "", s); split(s, a, " "); slots = a[1]
            t = $0; sub(/.*to all too \(/, "", t); split(t, b, " "); nodes = b[1]
            hb = slots + r * nodes
        }
        /nodal state: owned/ {owned = 1}
        /exchange a cycle, all ranks:/ {
            u = $0; sub(/.*all ranks: /, "", u); split(u, c, " "); p2p = c[1]
            w = $0; sub(/.*to every other rank\), /, "", w); split(w, e, " "); gat = e[1]
        }
        /^ +[0-9]+ +[0-9]+ +[0-9]+ +[0-9]+ +[0-9]+ +[0-9]+ +[0-9]+ +[0-9]+ +[0-9.]+ +[0-9]+$/ {own += $NF}
        /contact ghosts \(rank 0\)/ {
            g = $0; sub(/.*local search gathers /, "", g); split(g, gg, " "); gath = gg[1] "/" gg[5]
            q = $0; sub(/.*it applied /, "", q); split(q, qq, " "); pairs = qq[1]
            x = $0; sub(/.*at a search it sent /, "", x); split(x, xx, " "); srch = xx[1]
        }
        /contacts exchanged between the ranks/ {
            y = $0; sub(/.*ranks alone, /, "", y); split(y, yy, " "); cex = yy[1]
        }
        END {
            if (r == 1) {hb = 0; own = 0}
            if (owned) hb = p2p + gat
            if (gath == "") {gath = "-"; pairs = "-"}
            if (srch == "") srch = "-"
            if (cex == "") cex = "-"
            if (con == "") con = "-"
            printf "%6d %9.2f %10.1f %8.1f %9.1f %8.1f %8.1f%% %17s %17s %12s %14s %14s %16d %16d %18s %9s %14s %14s\n", r,
                tot, ns, 100 * halo / tot, 100 * ghost / tot, 100 * wait / tot, cs, mem, rss, el, arr, con, hb, own, gath,
                pairs, srch, cex
        }' $out/d3hsp
done
done
echo "bench-mpi: halo B/cycle: with owned nodes (d3hsp's nodal state), the halo's slots and velocities point-to-point, the contact surfaces' velocities with them to every other rank (all of a shell model's nodes: O(surface nodes x ranks) until ghosts by proximity), the beams' and ties' gathered; replicated, the force slots plus every node's forces to every rank (O(nodes x ranks)); own-node halo: each rank's halo nodes' forces out and motion back (O(partition surfaces)); srf sent/srch: the surface nodes rank 0 sent at a search to the ranks whose search box holds them (every surface node to every rank before); contacts B/cyc: the contacts found sent to their nodes' ranks a cycle, over all ranks"
