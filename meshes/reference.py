#!/usr/bin/env python3
"""Reference numbers from scikit-fem (an independent FEM code) on the committed meshes.

Cantilever (math note 9.5): plane stress, E = 1e7 Pa, nu = 0.3, L = 10 m, h = 1 m (cantilever.geo),
clamped on the physical curve "clamp" (x = 0: u_x = u_y = 0 at its nodes), a total tip shear
P = 1 N (per unit thickness) as a uniform traction -P/h on the tip edge x = L. Linear (P1)
triangles on exactly the nodes and triangles of cantilever_{1,2,3}.msh. Reported: the mean u_y over
the nodes of x = L. Writes reference.json beside this script; pbdda's tests read the json only.

Usage: pip install scikit-fem numpy; python3 meshes/reference.py
"""
import json
import os

import numpy as np
import skfem
from skfem.models.elasticity import lame_parameters, linear_elasticity

HERE = os.path.dirname(os.path.abspath(__file__))
E, NU, P, L, H = 1.0e7, 0.3, 1.0, 10.0, 1.0


def read_msh41_ascii(path):
    """Nodes and 3-node triangles of an MSH 4.1 ASCII file (enough for gmsh's own output)."""
    lines = open(path).read().split("\n")
    i = lines.index("$Nodes") + 1
    nblocks = int(lines[i].split()[0])
    i += 1
    coords = {}
    for _ in range(nblocks):
        n = int(lines[i].split()[3])
        tags = [int(t) for t in lines[i + 1 : i + 1 + n]]
        for k, t in enumerate(tags):
            x, y, _ = map(float, lines[i + 1 + n + k].split())
            coords[t] = (x, y)
        i += 1 + 2 * n
    i = lines.index("$Elements") + 1
    nblocks = int(lines[i].split()[0])
    i += 1
    tris = []
    for _ in range(nblocks):
        _, _, etype, n = map(int, lines[i].split())
        if etype == 2:
            tris += [list(map(int, lines[i + 1 + k].split()[1:])) for k in range(n)]
        i += 1 + n
    used = sorted({t for tri in tris for t in tri})
    index = {t: k for k, t in enumerate(used)}
    p = np.array([coords[t] for t in used]).T
    t = np.array([[index[a] for a in tri] for tri in tris]).T
    return p, t


def cantilever(path):
    p, t = read_msh41_ascii(path)
    mesh = skfem.MeshTri(p, t)
    e = skfem.ElementVector(skfem.ElementTriP1())
    basis = skfem.Basis(mesh, e)
    lam, mu = lame_parameters(E, NU)
    lam = 2 * lam * mu / (lam + 2 * mu)  # plane stress
    k = skfem.asm(linear_elasticity(lam, mu), basis)
    tip = mesh.facets_satisfying(lambda x: np.isclose(x[0], L))
    fbasis = skfem.FacetBasis(mesh, e, facets=tip)

    @skfem.LinearForm
    def traction(v, w):
        return -P / H * v.value[1]

    f = skfem.asm(traction, fbasis)
    clamp = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
    u = skfem.solve(*skfem.condense(k, f, D=clamp))
    tip_nodes = np.where(np.isclose(mesh.p[0], L))[0]
    uy = u[basis.nodal_dofs[1]]
    return float(np.mean(uy[tip_nodes])), int(t.shape[1])


def main():
    out = {
        "source": "meshes/reference.py (scikit-fem %s, P1 triangles)" % skfem.__version__,
        "cantilever": {
            "E": E, "nu": NU, "P": P, "L": L, "h": H, "plane": "stress",
            "quantity": "mean u_y over the nodes of x = L (m)",
            "meshes": {},
        },
    }
    for k in (1, 2, 3):
        name = "cantilever_%d.msh" % k
        v, n = cantilever(os.path.join(HERE, name))
        out["cantilever"]["meshes"][name] = {"triangles": n, "tip_uy": v}
        print(name, n, repr(v))
    with open(os.path.join(HERE, "reference.json"), "w") as fh:
        json.dump(out, fh, indent=2)
        fh.write("\n")


if __name__ == "__main__":
    main()
