"""Open a d3plot.xdmf with ParaView's XDMF reader (run it with pvpython,
from Debian's paraview package) and print, at the last time step, each
block's points, cells, arrays and bounds; the first line gives the number
of time steps and the first and last times. Exit 1 if the reader finds no
time steps or no cells.

    pvpython tools/xdmf_check.py OUTDIR/d3plot.xdmf
"""
import sys

from paraview.simple import UpdatePipeline, XDMFReader, servermanager


def main():
    r = XDMFReader(FileNames=[sys.argv[1]])
    ts = list(r.TimestepValues) if r.TimestepValues else []
    if not ts:
        print("no time steps")
        return 1
    print(f"time steps {len(ts)} first {ts[0]:.6g} last {ts[-1]:.6g}")
    UpdatePipeline(time=ts[-1], proxy=r)
    d = servermanager.Fetch(r)
    it = d.NewIterator()
    it.InitTraversal()
    cells = 0
    while not it.IsDoneWithTraversal():
        b = it.GetCurrentDataObject()
        cd, pd = b.GetCellData(), b.GetPointData()
        print(f"block points {b.GetNumberOfPoints()} cells {b.GetNumberOfCells()} "
              f"cell arrays {[cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays())]} "
              f"point arrays {[pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]} "
              f"bounds {[round(x, 6) for x in b.GetBounds()]}")
        cells += b.GetNumberOfCells()
        it.GoToNextItem()
    return 0 if cells > 0 else 1


if __name__ == "__main__":
    sys.exit(main())
