//! Contact laws and memory across steps: which interface applies to a pair, which contacts
//! form an edge-edge joint, and what each contact remembers from the previous step.

use super::{ContactGeom, ContactKey, Feature, JointKey};
use crate::model::Interface;
use std::collections::HashMap;

/// What a contact carries over to the next step (warm start and "was closed" memory).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Memory {
    /// Normal force, tangential force and rolling couple of the last step.
    pub force: [f64; 3],
    /// Closed at the end of the last step.
    pub closed: bool,
    /// An intact cemented joint (math note §4.5): created at t = 0, lost when it breaks.
    pub bonded: bool,
}

/// Memory of all contacts of the last step, sorted by persistent key. Contacts are detected
/// sorted by key, so the memory is built without sorting and read in detection order by a
/// merge ([`Lookup`]): no hashing in the step.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct ContactMemory {
    entries: Vec<(ContactKey, Memory)>,
}

impl ContactMemory {
    /// The memory of `entries` (sorted here if they are not, the first of equal keys kept).
    pub fn from_entries(mut entries: Vec<(ContactKey, Memory)>) -> ContactMemory {
        // a step's contacts come sorted and distinct: one pass tells
        if !entries.windows(2).all(|w| w[0].0 < w[1].0) {
            entries.sort_by_key(|e| e.0);
            entries.dedup_by_key(|e| e.0);
        }
        ContactMemory { entries }
    }

    /// A reader for keys asked in ascending order.
    pub fn lookup(&self) -> Lookup<'_> {
        Lookup { entries: &self.entries, at: 0 }
    }
}

/// Reads a [`ContactMemory`] by a merge with ascending keys; a key at or below the entry the merge
/// last passed is found by bisection instead.
pub struct Lookup<'a> {
    entries: &'a [(ContactKey, Memory)],
    at: usize,
}

impl Lookup<'_> {
    pub fn get(&mut self, key: &ContactKey) -> Option<Memory> {
        // the common case, a contact that persists: the entry after the last one read, found by
        // one test of equality, not the ordered comparisons below
        if let Some(e) = self.entries.get(self.at).filter(|e| e.0 == *key) {
            self.at += 1;
            return Some(e.1);
        }
        if self.at > 0 && self.entries[self.at - 1].0 >= *key {
            self.at = self.entries.partition_point(|e| e.0 < *key);
        }
        while self.at < self.entries.len() && self.entries[self.at].0 < *key {
            self.at += 1;
        }
        (self.entries.get(self.at).filter(|e| e.0 == *key)).map(|e| e.1)
    }
}

/// The interface law for a pair of materials: the entry naming the pair, else the default
/// entry (no `materials`, no `name`), else a smooth interface. A named entry without
/// `materials` is a joint's law only: edges tagged with it select it ([`shared_tag`]).
pub fn interface_for(interfaces: &[Interface], ma: usize, mb: usize) -> &Interface {
    let pair =
        |i: &&Interface| matches!(i.materials, Some([x, y]) if (x, y) == (ma, mb) || (y, x) == (ma, mb));
    interfaces
        .iter()
        .find(pair)
        .or_else(|| interfaces.iter().find(|i| i.materials.is_none() && i.name.is_none()))
        .unwrap_or(&Interface::SMOOTH)
}

/// The interface a contact's two features share through their edge tags (math note §4.14):
/// `tags(b)` is body b's [`crate::model::BodySpec::edge_interfaces`] (empty: untagged). An
/// edge-edge joint's contacts take the tag of the joint's two edges if they carry the same one;
/// a vertex-edge contact outside a joint the edge's tag if one of the two edges meeting at the
/// vertex carries it. `None`: the material pair's interface applies.
pub fn shared_tag<'a>(g: &ContactGeom, tags: impl Fn(usize) -> &'a [Option<usize>]) -> Option<usize> {
    if tags(g.a).is_empty() || tags(g.b).is_empty() {
        return None;
    }
    let tag = |body: u32, edge: u32| tags(body as usize).get(edge as usize).copied().flatten();
    if let Some(j) = g.joint {
        let lo = tag(j.body_lo, j.edge_lo)?;
        return (tag(j.body_hi, j.edge_hi) == Some(lo)).then_some(lo);
    }
    // the tags of the edges at a feature: an edge's own, or the two edges meeting at a vertex
    let near = |body: usize, f: Feature| {
        let t = tags(body);
        match f {
            Feature::Edge(e) => [t.get(e as usize).copied().flatten(), None],
            Feature::Vertex(v) => {
                let before = (v as usize + t.len() - 1) % t.len();
                [t[before], t.get(v as usize).copied().flatten()]
            }
            Feature::Outer | Feature::Inner => [None, None],
        }
    };
    let (x, y) = (near(g.a, g.key.fa), near(g.b, g.key.fb));
    x.into_iter().flatten().find(|t| y.contains(&Some(*t)))
}

/// [`interface_for`] of every pair of materials, found once per detection: the search over the
/// interfaces per contact grew with the number of materials.
pub struct InterfaceTable<'a> {
    materials: usize,
    table: Vec<&'a Interface>,
}

impl<'a> InterfaceTable<'a> {
    pub fn new(interfaces: &'a [Interface], materials: usize) -> Self {
        let table = (0..materials * materials)
            .map(|k| interface_for(interfaces, k / materials, k % materials))
            .collect();
        InterfaceTable { materials, table }
    }

    /// The interface of materials `ma` and `mb` (indices below the count given to [`Self::new`]).
    pub fn get(&self, ma: usize, mb: usize) -> &'a Interface {
        self.table[ma * self.materials + mb]
    }
}

/// For each contact, the index of the other contact of its edge-edge joint, if both ends
/// of the joint were found (math note §4.6).
pub fn joint_partners<'a>(contacts: impl ExactSizeIterator<Item = &'a ContactGeom>) -> Vec<Option<usize>> {
    let n = contacts.len();
    let mut by_joint: HashMap<JointKey, Vec<usize>> = HashMap::new();
    for (k, c) in contacts.enumerate() {
        if let Some(j) = c.joint {
            by_joint.entry(j).or_default().push(k);
        }
    }
    let mut partner = vec![None; n];
    for members in by_joint.values() {
        if let [k, l] = members[..] {
            partner[k] = Some(l);
            partner[l] = Some(k);
        }
    }
    partner
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::Feature;

    fn key(a: u32, b: u32) -> ContactKey {
        ContactKey { a, fa: Feature::Outer, b, fb: Feature::Vertex(0) }
    }

    /// What was stored under (a, b): a normal force of 10 a + b.
    fn remembered(a: u32, b: u32) -> Memory {
        Memory { force: [(10 * a + b) as f64, 0.0, 0.0], closed: true, bonded: false }
    }

    /// The memory built from unsorted entries, read by merge (ascending keys), by bisection
    /// (keys asked in descending order) and with each key asked twice: every key gets exactly
    /// what was stored under it, a key never stored gets nothing.
    #[test]
    fn lookup_finds_each_key_in_any_order() {
        let stored = [(3, 1), (0, 2), (1, 5), (2, 2)];
        let memory =
            ContactMemory::from_entries(stored.iter().map(|&(a, b)| (key(a, b), remembered(a, b))).collect());
        let asked = [(0, 1), (0, 2), (1, 5), (2, 0), (2, 2), (3, 1), (4, 0)];
        let want =
            |stored: &[(u32, u32)], (a, b): (u32, u32)| stored.contains(&(a, b)).then(|| remembered(a, b));
        let mut lookup = memory.lookup();
        for &k in &asked {
            assert_eq!(lookup.get(&key(k.0, k.1)), want(&stored, k), "ascending {k:?}");
        }
        let mut lookup = memory.lookup();
        for &k in asked.iter().rev() {
            assert_eq!(lookup.get(&key(k.0, k.1)), want(&stored, k), "descending {k:?}");
        }
        // each key twice in a row: the second ask comes after the merge has passed the key
        let mut lookup = memory.lookup();
        for &k in asked.iter().flat_map(|k| [k, k]) {
            assert_eq!(lookup.get(&key(k.0, k.1)), want(&stored, k), "twice {k:?}");
        }
    }

    /// `from_entries` keeps the first of equal keys (its doc), whether the entries come sorted
    /// (the strict-order pass then fails on the tie) or not: a sorted input with a duplicate
    /// would otherwise keep both, and the merge would read the second as the next key's.
    #[test]
    fn memory_keeps_the_first_of_equal_keys() {
        let first = remembered(1, 1);
        let second = Memory { force: [-7.0, 0.0, 0.0], closed: false, bonded: true };
        for entries in [
            vec![(key(0, 1), remembered(0, 1)), (key(1, 1), first), (key(1, 1), second)],
            vec![(key(1, 1), first), (key(0, 1), remembered(0, 1)), (key(1, 1), second)],
        ] {
            let memory = ContactMemory::from_entries(entries);
            assert_eq!(memory.entries.len(), 2);
            let mut lookup = memory.lookup();
            assert_eq!(lookup.get(&key(0, 1)), Some(remembered(0, 1)));
            assert_eq!(lookup.get(&key(1, 1)), Some(first));
        }
    }

    /// The table gives each pair of materials the interface [`interface_for`] finds: the entry
    /// naming the pair in either order, else the default entry (here: friction 0.3), and
    /// without a default the smooth interface; checked for every ordered pair of three
    /// materials, with and without the default.
    #[test]
    fn interface_table_is_interface_for_of_every_pair() {
        let named =
            |m: [usize; 2], friction: f64| Interface { materials: Some(m), friction, ..Interface::SMOOTH };
        let default = Interface { friction: 0.3, ..Interface::SMOOTH };
        let with_default = vec![named([0, 1], 0.5), default, named([2, 2], 0.7)];
        let without = vec![named([1, 0], 0.5), named([2, 2], 0.7)];
        for interfaces in [&with_default, &without] {
            let table = InterfaceTable::new(interfaces, 3);
            for (a, b) in (0..3).flat_map(|a| (0..3).map(move |b| (a, b))) {
                let expected = match (a.min(b), a.max(b)) {
                    (0, 1) => 0.5,
                    (2, 2) => 0.7,
                    _ if interfaces.len() == 3 => 0.3,
                    _ => 0.0,
                };
                assert_eq!(table.get(a, b).friction, expected, "materials {a} and {b}");
                assert!(std::ptr::eq(table.get(a, b), interface_for(interfaces, a, b)));
            }
        }
    }
}
