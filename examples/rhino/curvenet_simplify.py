#! python3
# r: curvenet
"""Rhino 8: simplify the selected curves on a surface mesh with curvenet.

Select the sketch's curves and (optionally) the surface mesh, run this script from Rhino's
script editor, answer the budget and the curves to keep; the result is added as layers under
`curvenet` (kept and removed curves, the kept curves at equilibrium and along the worst-case
mode). The work is done by `curvenet.rhino.simplify_geometry` and `curvenet.rhino.result_layers`,
tested with rhino3dm geometry; this file is only the Rhino-side shell and is untested inside
Rhino (see README.md beside it).
"""

import Rhino
import rhinoscriptsyntax as rs
import scriptcontext as sc
import System.Drawing

import curvenet
from curvenet import rhino as cn_rhino


def pick():
    curve_ids = rs.GetObjects("Curves of the sketch", rs.filter.curve, preselect=True)
    if not curve_ids:
        return None
    mesh_id = rs.GetObject("Surface mesh (Enter for none)", rs.filter.mesh)
    budget = rs.GetReal("Budget (fraction of the total length to keep)", 0.5, 0.01, 0.99)
    if budget is None:
        return None
    keep_ids = rs.GetObjects("Curves to keep (Enter for none)", rs.filter.curve) or []
    curves = [rs.coercecurve(i) for i in curve_ids]
    mesh = rs.coercemesh(mesh_id) if mesh_id else None
    keep = [k for k, i in enumerate(curve_ids) if i in set(keep_ids)]
    return curves, mesh, budget, keep


def layer_index(path, color):
    index = sc.doc.Layers.FindByFullPath(path, -1)
    if index >= 0:
        return index
    parent_path, _, name = path.rpartition("::")
    layer = Rhino.DocObjects.Layer()
    layer.Name = name
    layer.Color = System.Drawing.Color.FromArgb(*color)
    if parent_path:
        layer.ParentLayerId = sc.doc.Layers[layer_index(parent_path, (0, 0, 0))].Id
    return sc.doc.Layers.Add(layer)


def add(layers):
    for lay in layers:
        index = layer_index(lay.path, lay.color)
        for name, points, closed in lay.objects:
            pts = [Rhino.Geometry.Point3d(*map(float, p)) for p in points]
            if closed:
                pts.append(pts[0])
            attrs = Rhino.DocObjects.ObjectAttributes()
            attrs.LayerIndex = index
            attrs.Name = name
            attrs.SetUserString("curvenet.curve", name.split()[-1])
            sc.doc.Objects.AddCurve(Rhino.Geometry.PolylineCurve(pts), attrs)
    sc.doc.Views.Redraw()


def main():
    picked = pick()
    if picked is None:
        return
    curves, mesh, budget, keep = picked
    tolerance = sc.doc.ModelAbsoluteTolerance

    def progress(it):
        Rhino.RhinoApp.SetCommandPrompt(
            "curvenet: {} curves, lambda {:.4e}".format(len(it.curves), it.lambda_eq))
        Rhino.RhinoApp.Wait()

    try:
        result = cn_rhino.simplify_geometry(curves, mesh, budget=budget, keep=keep,
                                            tolerance=tolerance, progress=progress)
    except curvenet.InputError as e:
        rs.MessageBox("curvenet: {}".format(e))
        return
    for w in result.warnings:
        print("curvenet: " + w)
    add(cn_rhino.result_layers(result))
    print(result)


if __name__ == "__main__":
    main()
