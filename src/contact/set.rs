//! Contact laws and memory across steps: which interface applies to a pair, which contacts
//! form an edge-edge joint, and what each contact remembers from the previous step.

use super::{ContactGeom, ContactKey, JointKey};
use crate::model::Interface;
use std::collections::HashMap;

/// What a contact carries over to the next step (warm start and "was closed" memory).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Memory {
    /// Normal force, tangential force and rolling couple of the last step.
    pub force: [f64; 3],
    /// Closed at the end of the last step.
    pub closed: bool,
    /// An intact cemented joint (math note §4.5): created at t = 0, lost when it breaks.
    pub bonded: bool,
}

/// Memory of all contacts of the last step, by persistent key.
pub type ContactMemory = HashMap<ContactKey, Memory>;

/// The interface law for a pair of materials: the entry naming the pair, else the default
/// entry (no `materials`), else a smooth interface.
pub fn interface_for(interfaces: &[Interface], ma: usize, mb: usize) -> &Interface {
    let pair =
        |i: &&Interface| matches!(i.materials, Some([x, y]) if (x, y) == (ma, mb) || (y, x) == (ma, mb));
    interfaces
        .iter()
        .find(pair)
        .or_else(|| interfaces.iter().find(|i| i.materials.is_none()))
        .unwrap_or(&Interface::SMOOTH)
}

/// For each contact, the index of the other contact of its edge-edge joint, if both ends
/// of the joint were found (math note §4.6).
pub fn joint_partners(contacts: &[ContactGeom]) -> Vec<Option<usize>> {
    let mut by_joint: HashMap<JointKey, Vec<usize>> = HashMap::new();
    for (k, c) in contacts.iter().enumerate() {
        if let Some(j) = c.joint {
            by_joint.entry(j).or_default().push(k);
        }
    }
    let mut partner = vec![None; contacts.len()];
    for members in by_joint.values() {
        if let [k, l] = members[..] {
            partner[k] = Some(l);
            partner[l] = Some(k);
        }
    }
    partner
}
