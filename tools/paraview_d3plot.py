"""Render the last state of a run's d3plot family with ParaView's LS-DYNA
reader (an independent reader of the binary layout) to a PNG.

    pvpython --force-offscreen-rendering tools/paraview_d3plot.py RUN OUT.png [ARRAY]
    xvfb-run -a pvpython tools/paraview_d3plot.py RUN OUT.png [ARRAY]

RUN holds `d3plot` (and its members d3plot01, ...); ARRAY is the shell
cell array to colour by (default EffPlastStrn, the mid-surface layer's
effective plastic strain as VTK names it). Prints the states and the time
shown.
"""
import os
import sys

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetAnimationScene, LSDynaReader, ResetCamera,
                             SaveScreenshot, Show, GetScalarBar)


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 1
    run, png = sys.argv[1], sys.argv[2]
    array = sys.argv[3] if len(sys.argv) > 3 else "EffPlastStrn"
    reader = LSDynaReader(FileName=os.path.join(run, "d3plot"))
    reader.UpdatePipelineInformation()
    times = list(reader.TimestepValues)
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = times[-1]
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = [1200, 900]
    view.Background = [1.0, 1.0, 1.0]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    shown = Show(reader, view)
    ColorBy(shown, ("CELLS", array))
    shown.RescaleTransferFunctionToDataRange(True, False)
    shown.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(shown.LookupTable, view)
    bar.Title = array
    bar.TitleColor = [0, 0, 0]
    bar.LabelColor = [0, 0, 0]
    view.CameraPosition = [0.35, -0.45, 0.3]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    ResetCamera(view)
    SaveScreenshot(png, view, ImageResolution=[1200, 900])
    print(f"{len(times)} states; the last, t = {times[-1]:.6g}, coloured by {array}, in {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
