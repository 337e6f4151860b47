"""The README's picture: the last mesh of the example (bash quickstart.sh
example), coloured by the local error eps_E, rendered by ParaView.

Usage: xvfb-run -a pvbatch doc/figures/front_page.py \
           output-block-adaptive/solution-01.vtu doc/figures/front-page.png
"""
import sys

from paraview.simple import (ColorBy, CreateRenderView, GetColorTransferFunction,
                             GetScalarBar, Render, SaveScreenshot, Show,
                             XMLUnstructuredGridReader)

source, picture = sys.argv[1:3]
mesh = XMLUnstructuredGridReader(FileName=[source])
view = CreateRenderView()
view.ViewSize = [800, 640]
view.OrientationAxesVisibility = 0
if hasattr(view, "UseColorPaletteForBackground"):
    view.UseColorPaletteForBackground = 0
view.Background = [1.0, 1.0, 1.0]
view.InteractionMode = "2D"

display = Show(mesh, view)
display.SetRepresentationType("Surface With Edges")
display.EdgeColor = [0.85, 0.85, 0.85]
# (deal.II writes cell data as values at the vertices of each cell)
ColorBy(display, ("POINTS", "eps_E"))
colours = GetColorTransferFunction("eps_E")
colours.ApplyPreset("Viridis (matplotlib)", True)
# (logarithmic: the optimal mesh spreads eps_E evenly, its singular corners
# stand out)
low, high = mesh.PointData["eps_E"].GetRange()
colours.MapControlPointsToLogSpace()
colours.UseLogScale = 1
colours.RescaleTransferFunction(max(low, high * 1e-3), high)
display.SetScalarBarVisibility(view, True)
bar = GetScalarBar(colours, view)
bar.Title = "eps_E (final mesh)"
bar.ComponentTitle = ""
bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
bar.WindowLocation = "Any Location"
bar.Position = [0.86, 0.15]
bar.ScalarBarLength = 0.7

view.ResetCamera()
view.CameraParallelScale = 0.53
Render(view)
SaveScreenshot(picture, view, ImageResolution=[800, 640])
