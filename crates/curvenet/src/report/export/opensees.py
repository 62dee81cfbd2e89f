
# Run as it is (`python THIS_FILE`, with `pip install openseespy`): builds the model in
# OpenSees, computes its lowest natural frequencies, its linear self-weight deflection and
# the largest deflection under each of the run's load cases (linear), and prints them as one
# JSON line in the model's units. MODEL is curvenet's neutral
# structural JSON (`curvenet export DIR --format structural`): nodes, ties (joints: shared
# translations, free relative rotations), elastic beams per rod edge, supports, spin holds of
# straight rods, supports along directions that are not world axes (skew: stiff springs),
# lumped masses and load cases.
import json
import math
import sys

import openseespy.opensees as ops


def build(model):
    """The model in a fresh OpenSees domain (3 dimensions, 6 degrees of freedom a node)."""
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for n in model["nodes"]:
        ops.node(n["id"], *n["xyz"])
    for s in model["supports"]:
        ops.fix(s["node"], *[1 if f else 0 for f in s["fixed"]])
    for t in model["ties"]:
        for other in t["nodes"][1:]:
            ops.equalDOF(t["nodes"][0], other, 1, 2, 3)
    materials = {m["id"]: m for m in model["materials"]}
    sections = {s["id"]: s for s in model["sections"]}
    transforms = {}
    for e in model["elements"]:
        key = tuple(e["vecxz"])
        if key not in transforms:
            transforms[key] = len(transforms) + 1
            ops.geomTransf("Linear", transforms[key], *key)
        m, s = materials[e["material"]], sections[e["section"]]
        ops.element("elasticBeamColumn", e["id"], *e["nodes"], s["area"], m["young"],
                    m["shear"], s["torsion"], s["second_moment"], s["second_moment"],
                    transforms[key])
    ground = len(model["nodes"])
    tag = len(model["elements"])
    for i, h in enumerate(model["spin_holds"], start=1):
        node = ops.nodeCoord(h["node"])
        ops.node(ground + i, *node)
        ops.fix(ground + i, 1, 1, 1, 1, 1, 1)
        ops.uniaxialMaterial("Elastic", i, h["stiffness"])
        ax = h["axis"]
        yp = [0.0, 0.0, 0.0]
        yp[min(range(3), key=lambda k: abs(ax[k]))] = 1.0
        ops.element("zeroLength", tag + i, ground + i, h["node"], "-mat", i, "-dir", 4,
                    "-orient", *ax, *yp)
    # A skew support: a zeroLength element from a fixed ground node, its local x along the
    # held direction, a spring of curvenet's anchor stiffness in that direction only.
    ground += len(model["spin_holds"])
    tag += len(model["spin_holds"])
    mat = len(model["spin_holds"])
    for i, s in enumerate(model.get("skew_supports", []), start=1):
        ops.node(ground + i, *ops.nodeCoord(s["node"]))
        ops.fix(ground + i, 1, 1, 1, 1, 1, 1)
        ops.uniaxialMaterial("Elastic", mat + i, s["stiffness"])
        d = s["direction"]
        yp = [0.0, 0.0, 0.0]
        yp[min(range(3), key=lambda k: abs(d[k]))] = 1.0
        ops.element("zeroLength", tag + i, ground + i, s["node"], "-mat", mat + i, "-dir", 1,
                    "-orient", *d, *yp)
    for m in model["masses"]:
        t, r = m["translational"], m["rotational"]
        ops.mass(m["node"], t, t, t, r, r, r)


def solver():
    """How the equations are solved: the ties eliminated by transformation."""
    ops.wipeAnalysis()
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.algorithm("Linear")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")


def frequencies(model):
    """The lowest natural frequencies, Hz (None for a zero or negative mode)."""
    solver()
    n = min(model["frequencies"], 6 * len(model["nodes"]) - 1)
    values = ops.eigen("-genBandArpack", n)
    return [math.sqrt(v) / (2 * math.pi) if v > 0 else None for v in values]


def static(model, case):
    """The largest node displacement under the load case, linear, on the model built."""
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    for load in case["nodal"]:
        ops.load(load["node"], *load["force"], 0.0, 0.0, 0.0)
    solver()
    if ops.analyze(1) != 0:
        return None
    return max(math.sqrt(sum(d * d for d in ops.nodeDisp(n["id"])[:3]))
               for n in model["nodes"])


def main():
    build(MODEL)
    result = {"units": MODEL["units"]["length"], "frequencies_hz": frequencies(MODEL)}
    cases = []
    for case in MODEL["load_cases"]:
        build(MODEL)
        cases.append({"name": case["name"], "max_deflection": static(MODEL, case)})
    # The structure's own weight first; then the run's load cases and combinations.
    result["self_weight_max_deflection"] = cases[0]["max_deflection"]
    result["load_cases"] = cases[1:]
    print(json.dumps(result))


if __name__ == "__main__":
    sys.exit(main())
