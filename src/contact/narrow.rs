//! Narrow phase (placeholder until implemented).
use super::{BodyShape, ContactGeom};
pub fn pair_contacts(_i: usize, _j: usize, _si: &BodyShape, _sj: &BodyShape, _threshold: f64, _out: &mut Vec<ContactGeom>) {
    todo!()
}
