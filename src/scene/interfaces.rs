//! `[[interface]]` tables: the contact laws, their material pairs, names and friction.

use std::collections::HashMap;

use toml::Spanned;

use super::check::{
    Check, Names, fail, non_negative, optional, or_default, real, resolve, unique_names, unit_interval,
};
use super::raw;
use crate::model::Interface;

pub(super) fn interfaces(raw: &[Spanned<raw::Interface>], materials: &Names) -> Check<Vec<Interface>> {
    // unordered material pair (None: the default entry) -> index of the entry that defines it
    let mut seen: HashMap<Option<[usize; 2]>, usize> = HashMap::new();
    let mut list = Vec::with_capacity(raw.len());
    for (i, r) in raw.iter().enumerate() {
        let (header, r) = (r.span(), r.get_ref());
        let interface = interface(r, materials)?;
        let pair = interface.materials.map(|[a, b]| [a.min(b), a.max(b)]);
        // a named interface without materials is a joint's law, not a default
        let joint_only = pair.is_none() && interface.name.is_some();
        if let Some(first) = (!joint_only).then(|| seen.insert(pair, i)).flatten() {
            let (span, what) = match &r.materials {
                None => (header, "a second default interface (one without `materials`)"),
                Some(m) => (m.span(), "a second interface for the same pair of materials"),
            };
            let message = format!("{what}; interface[{first}] already covers it");
            return fail(span, message);
        }
        list.push(interface);
    }
    Ok(list)
}

/// Name -> index of the named interfaces; names are unique.
pub(super) fn interface_names(raw: &[Spanned<raw::Interface>]) -> Check<Names<'_>> {
    let mut names = Names::new();
    for (i, r) in raw.iter().enumerate() {
        let Some(name) = &r.get_ref().name else { continue };
        // checked one at a time, so that a duplicate names the interface index of the file
        unique_names(std::iter::once(name), "interface")?;
        if let Some(first) = names.insert(name.get_ref().as_str(), i) {
            let message = format!(
                "duplicate interface name \"{}\" (already used by interface[{first}])",
                name.get_ref()
            );
            return fail(name.span(), message);
        }
    }
    Ok(names)
}

fn interface(r: &raw::Interface, materials: &Names) -> Check<Interface> {
    let pair = |m: &Spanned<_>, _: &str| material_pair(m, materials);
    Ok(Interface {
        name: r.name.as_ref().map(|n| n.get_ref().clone()),
        materials: optional(&r.materials, "materials", pair)?,
        friction: friction(r)?,
        cohesion: or_default(&r.cohesion, "cohesion", non_negative, 0.0)?,
        tensile_strength: or_default(&r.tensile_strength, "tensile_strength", non_negative, 0.0)?,
        rolling: or_default(&r.rolling, "rolling", non_negative, 0.0)?,
        restitution: or_default(&r.restitution, "restitution", unit_interval, 1.0)?,
    })
}

fn material_pair(m: &Spanned<Vec<Spanned<String>>>, materials: &Names) -> Check<[usize; 2]> {
    match m.get_ref().as_slice() {
        [a, b] => Ok([resolve(materials, a, "material")?, resolve(materials, b, "material")?]),
        other => fail(m.span(), format!("materials must name 2 materials (got {})", other.len())),
    }
}

/// μ from `friction`, or tan of `friction_angle` (degrees, below 90); 0 when neither is given.
fn friction(r: &raw::Interface) -> Check<f64> {
    match (&r.friction, &r.friction_angle) {
        (Some(_), Some(angle)) => fail(angle.span(), "give either `friction` or `friction_angle`, not both"),
        (Some(mu), None) => non_negative(mu, "friction"),
        (None, Some(angle)) => {
            let below_90 = |a| (0.0..90.0).contains(&a);
            let degrees = real(angle, "friction_angle", "be at least 0 and below 90", below_90)?;
            Ok(degrees.to_radians().tan())
        }
        (None, None) => Ok(0.0),
    }
}
