//! Mesh convergence of the meshed cantilever (math note §9.5): the three shipped meshes
//! `meshes/cantilever_{1,2,3}.msh` (gmsh lc = 0.5, 0.25, 0.125 by `meshes/cantilever.geo`),
//! clamped by `fixed_nodes = ["clamp"]`, loaded by a uniform tip shear of P = 1 N over the edge
//! x = L (a `[[traction]]` on the physical group `tip`, whose nodal loads are the consistent
//! ones). Against peer code: scikit-fem's P1 solution on the same meshes
//! (`meshes/reference.json`, mean u_y over the tip nodes); the observed order and the
//! Richardson-extrapolated tip deflection come from [`crate::cli::sweep::richardson`] (Celik et
//! al. 2008) with the nominal sizes lc, and are compared with the same extrapolation of
//! scikit-fem's values and with beam theory.

use super::{Row, exact, row, run, world_from_disk};
use crate::cli::sweep::richardson::extrapolate;
use crate::world::World;
use miette::Result;

const REFERENCE: &str = include_str!("../../../meshes/reference.json");
const MESHES: [(&str, &[u8]); 3] = [
    ("cantilever_1.msh", include_bytes!("../../../meshes/cantilever_1.msh")),
    ("cantilever_2.msh", include_bytes!("../../../meshes/cantilever_2.msh")),
    ("cantilever_3.msh", include_bytes!("../../../meshes/cantilever_3.msh")),
];
/// gmsh's characteristic length of each mesh (`meshes/cantilever.geo`, halved each time).
const SIZES: [f64; 3] = [0.5, 0.25, 0.125];

/// The number after `"key":` following `"mesh":` in reference.json.
fn reference(mesh: &str, key: &str) -> Result<f64> {
    let mut at = 0;
    for k in [mesh, key] {
        let quoted = format!("\"{k}\":");
        at += REFERENCE[at..].find(&quoted).ok_or_else(|| miette::miette!("reference.json: no {k}"))?
            + quoted.len();
    }
    let v = &REFERENCE[at..];
    let end = v.find(['\n', ',', '}']).unwrap_or(v.len());
    v[..end].trim().parse().map_err(|_| miette::miette!("reference.json: {mesh}.{key} is not a number"))
}

/// The cantilever scene on mesh `file` (static relaxation: dt = 1 s with ρ = 1 makes the mass
/// term 2e-3 of the tip stiffness, so 12 steps converge to round-off).
fn scene(file: &str) -> String {
    format!(
        "[scene]\nname = \"meshed cantilever, uniform tip shear\"\n[time]\nstep = 1.0\nsteps = 12\n\
         [physics]\ngravity = [0.0, 0.0]\nvelocity_carry = 0.0\nplane = \"stress\"\n\
         [[material]]\nname = \"steel\"\ndensity = 1.0\nyoung = 1.0e7\npoisson = 0.3\n\
         [[body]]\nname = \"beam\"\nshape = \"mesh\"\nfile = \"../meshes/{file}\"\nphysical = \"beam\"\n\
         fixed_nodes = [\"clamp\"]\nmaterial = \"steel\"\n\
         [[traction]]\nbody = \"beam\"\ngroup = \"tip\"\nstress = [0.0, 0.0, -1.0]\n"
    )
}

/// Mean u_y over the mesh nodes that start on x = L = 10.
fn tip_uy(world: &World) -> Result<f64> {
    let fe = world.bodies.first().and_then(|b| b.mesh.as_ref()).ok_or_else(|| miette::miette!("no mesh"))?;
    let tip: Vec<usize> = (0..fe.nodes.len()).filter(|&n| (fe.reference[n].x - 10.0).abs() < 1e-9).collect();
    Ok(tip.iter().map(|&n| fe.displacement[n].y).sum::<f64>() / tip.len().max(1) as f64)
}

/// Rows: each mesh's tip deflection against scikit-fem's, then the observed order, the
/// extrapolated deflection against scikit-fem's extrapolated one and against beam theory.
pub(super) fn cantilever_meshes() -> Result<Vec<Row>> {
    let e = "mesh: cantilever convergence";
    let (mut ours, mut peer) = ([0.0; 3], [0.0; 3]);
    let mut rows = Vec::new();
    for (k, (name, bytes)) in MESHES.iter().enumerate() {
        let file = format!("meshes/{name}");
        let mut w =
            world_from_disk("mesh_cantilever_traction.toml", &scene(name), &[(file.as_str(), *bytes)], &[])?;
        run(&mut w, 12, |_, _| {})?;
        (ours[k], peer[k]) = (tip_uy(&w)?, reference(name, "tip_uy")?);
        let why = "meshes/reference.json (scikit-fem, P1, same mesh); 1e-5 relative: the steps \
                   accumulate on the updated geometry, rotations ~6e-5";
        let q = format!("tip u_y, {name} (lc = {}) [m]", SIZES[k]);
        rows.push(row(e, q, None, peer[k], ours[k]).tol(1e-5 * peer[k].abs(), why));
    }
    // finest first, as extrapolate takes them
    let fine = |v: [f64; 3]| [v[2], v[1], v[0]];
    let h = fine(SIZES);
    let x = extrapolate("tip u_y", h, fine(ours));
    let reference = extrapolate("tip u_y", h, fine(peer));
    let why = "Tri3 converges at O(h²); 0.1: the coarse mesh is near the edge of the asymptotic \
               range (scikit-fem's values give 2.03)";
    rows.push(
        row(e, "observed order of tip u_y".into(), None, 2.0, x.order.unwrap_or(f64::NAN)).tol(0.1, why),
    );
    let peer_ext = reference.extrapolated.unwrap_or(f64::NAN);
    let ext = x.extrapolated.unwrap_or(f64::NAN);
    let why = "the same Richardson extrapolation of reference.json's values; 0.5 %";
    rows.push(
        row(e, "extrapolated tip u_y vs scikit-fem [m]".into(), None, peer_ext, ext)
            .tol(5e-3 * peer_ext.abs(), why),
    );
    let beam = exact::mesh_cantilever_tip();
    let why = "beam theory P L³/(3EI) + P L/(κ G A); 1 %: plane stress differs from the beam by the \
               clamp's local effect (0.35 %)";
    rows.push(
        row(e, "extrapolated tip u_y vs beam theory [m]".into(), None, beam, ext).tol(1e-2 * beam.abs(), why),
    );
    Ok(rows)
}
