//! Broad phase (placeholder until implemented).
use super::BodyShape;
pub fn candidate_pairs(_shapes: &[BodyShape], _fixed: &[bool], _threshold: f64) -> Vec<(usize, usize)> {
    todo!()
}
