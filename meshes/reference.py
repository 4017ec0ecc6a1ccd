#!/usr/bin/env python3
"""Reference numbers from scikit-fem (an independent FEM code) on the committed meshes.

Cantilever (math note 9.5): plane stress, E = 1e7 Pa, nu = 0.3, L = 10 m, h = 1 m (cantilever.geo),
clamped on the physical curve "clamp" (x = 0: u_x = u_y = 0 at its nodes), a total tip shear
P = 1 N (per unit thickness) as a uniform traction -P/h on the tip edge x = L. Linear (P1)
triangles on exactly the nodes and triangles of cantilever_{1,2,3}.msh. Reported: the mean u_y over
the nodes of x = L. Writes reference.json beside this script; pbdda's tests read the json only.

Bolted slab (examples/mesh_bolted_slab.toml): slab.msh, plane stress, E = 1e9 Pa, nu = 0.25,
rho = 2500 kg/m3 under g = 10 m/s2 and, for the linear regime, 0.1 m/s2 (P1 body force), hanging from two vertical bolts (E_b = 2e11 Pa,
A = 5e-4 m2, l = 0.8 m, upper ends fixed) anchored at (0.25, 0.2) and (1.75, 0.2). Each bolt is a
spring k = E_b A / l between ground and its anchor, the anchor moving with the three nodes of the
triangle holding it by their area coordinates w: K[v_i, v_j] += k w_i w_j (pbdda's coupling, math
note 6 and 9.2), plus its tension's geometric stiffness N / l across the bolt, N = W / 2 (what pbdda
adds, math note 10.7; it only holds the slab sideways here). Reported: the displacement of the
monitor point (1.0, 0.15), interpolated in its triangle.

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


def cross2(a, b):
    return a[0] * b[1] - a[1] * b[0]


def locate(p, t, x):
    """Triangle index and area coordinates of point x (it must lie inside a triangle)."""
    for e in range(t.shape[1]):
        a, b, c = (p[:, t[k, e]] for k in range(3))
        area2 = cross2(b - a, c - a)
        la = cross2(b - x, c - x) / area2
        lb = cross2(c - x, a - x) / area2
        lam = np.array([la, lb, 1.0 - la - lb])
        if lam.min() >= -1e-12:
            return e, lam
    raise ValueError("point outside the mesh")


def bolted_slab(path, g):
    rho, eb, ab, lb = 2500.0, 2.0e11, 5.0e-4, 0.8
    p, t = read_msh41_ascii(path)
    mesh = skfem.MeshTri(p, t)
    e = skfem.ElementVector(skfem.ElementTriP1())
    basis = skfem.Basis(mesh, e)
    lam, mu = lame_parameters(1.0e9, 0.25)
    lam = 2 * lam * mu / (lam + 2 * mu)  # plane stress
    k = skfem.asm(linear_elasticity(lam, mu), basis).tolil()

    @skfem.LinearForm
    def weight(v, w):
        return -rho * g * v.value[1]

    f = skfem.asm(weight, basis)
    area = sum(0.5 * abs(cross2(p[:, t[1, i]] - p[:, t[0, i]], p[:, t[2, i]] - p[:, t[0, i]])) for i in range(t.shape[1]))
    tension = rho * g * area / 2.0
    for anchor in ((0.25, 0.2), (1.75, 0.2)):
        el, w = locate(p, t, np.array(anchor))
        nodes = t[:, el]
        for comp, stiff in ((1, eb * ab / lb), (0, tension / lb)):
            dofs = basis.nodal_dofs[comp][nodes]
            for i in range(3):
                for j in range(3):
                    k[dofs[i], dofs[j]] += stiff * w[i] * w[j]
    u = skfem.solve(k.tocsr(), f)
    el, w = locate(p, t, np.array((1.0, 0.15)))
    nodes = t[:, el]
    ux = float(np.dot(w, u[basis.nodal_dofs[0][nodes]]))
    uy = float(np.dot(w, u[basis.nodal_dofs[1][nodes]]))
    return ux, uy, int(t.shape[1])


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
    ux, uy, n = bolted_slab(os.path.join(HERE, "slab.msh"), 10.0)
    ux_small, uy_small, _ = bolted_slab(os.path.join(HERE, "slab.msh"), 0.1)
    out["bolted_slab"] = {
        "mesh": "slab.msh", "triangles": n, "plane": "stress", "E": 1.0e9, "nu": 0.25, "rho": 2500.0,
        "bolts": {"E": 2.0e11, "A": 5.0e-4, "l": 0.8, "anchors": [[0.25, 0.2], [1.75, 0.2]]},
        "quantity": "displacement (m) of the monitor point (1.0, 0.15) under g = 10 and g = 0.1 m/s2",
        "ux_g10": ux, "uy_g10": uy, "ux_g0.1": ux_small, "uy_g0.1": uy_small,
    }
    print("slab.msh", n, repr(uy), repr(uy_small))
    with open(os.path.join(HERE, "reference.json"), "w") as fh:
        json.dump(out, fh, indent=2)
        fh.write("\n")


if __name__ == "__main__":
    main()
