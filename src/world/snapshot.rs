//! The state of a [`World`] between two steps, as a checkpoint saves it ([`World::state`]) and
//! `pbdda resume` loads it ([`World::from_state`]): everything the next step reads that is not
//! a function of the scene. What the scene gives (the model, the bodies' constants, a mesh's
//! sparse pattern) is built from the scene again; the model then takes the settings of the
//! stage the state is in, as the stage's start set them.
//!
//! The state holds the bodies (outlines, centroids, rotations, velocities, strains, stresses,
//! meshes' nodes and element stresses), the tracked points, the connectors (forces, plastic
//! strain, yield and broken flags), the DOF map, the stage state, the factorized step
//! stiffness with its kept factors ([`crate::cluster::FlexState`]), the contact memory (forces
//! and closed/bonded flags of the last step's contacts), the broken cemented joints, the
//! penetration allowance, time and step, and the VI solver's MPRGP step-length guess. The step's
//! other scratch (W's storage, the broad phase's pair cache, the solver's work vectors) is not
//! state: a step fills it before reading it, or it gives the same answer however it was
//! filled. A step that starts from the loaded state is bit for bit the step the saved run took
//! (tests/io/resume_examples.rs checks every example).

use super::{Settings, StageState, TrackedPoint, World};
use crate::body::Body;
use crate::cluster::{FlexState, Flexibility};
use crate::connector::Connector;
use crate::contact::ContactKey;
use crate::contact::set::ContactMemory;
use crate::dofs::DofMap;
use crate::model::Model;
use serde::{Deserialize, Serialize};

/// The saved state (field order is the binary layout: a change needs a new format version in
/// `crate::checkpoint`).
#[derive(Serialize, Deserialize)]
struct State {
    step_index: usize,
    time: f64,
    threshold: f64,
    feature: f64,
    allowance: f64,
    started: bool,
    h: f64,
    bodies: Vec<Body>,
    load_points: Vec<TrackedPoint>,
    monitors: Vec<TrackedPoint>,
    connectors: Vec<Connector>,
    dofs: DofMap,
    stage: StageState,
    flex: FlexState,
    memory: ContactMemory,
    /// The broken joints' contacts, sorted (a set has no stable order).
    broken: Vec<ContactKey>,
    step_length: Option<f64>,
}

/// Why a saved state does not load.
#[derive(Debug, thiserror::Error)]
pub enum StateError {
    #[error("the state cannot be decoded: {0}")]
    Decode(String),
    #[error("the state has {saved} {what}, the scene {scene}")]
    Mismatch { what: &'static str, saved: usize, scene: usize },
    #[error("the state's sparse factor does not load: {0}")]
    Factor(String),
}

impl World {
    /// The state between steps, encoded (module docs). Call it between two steps.
    pub fn state(&self) -> Vec<u8> {
        let mut broken: Vec<ContactKey> = self.broken.iter().copied().collect();
        broken.sort_unstable();
        let state = State {
            step_index: self.step_index,
            time: self.time,
            threshold: self.threshold,
            feature: self.feature,
            allowance: self.allowance,
            started: self.started,
            h: self.h,
            bodies: self.bodies.clone(),
            load_points: self.load_points.clone(),
            monitors: self.monitors.clone(),
            connectors: self.connectors.clone(),
            dofs: self.dofs.clone(),
            stage: self.stage.clone(),
            flex: self.flex.state(),
            memory: self.memory.clone(),
            broken,
            step_length: self.pipeline.vi.step_length(),
        };
        // encoding into memory fails only on an unrepresentable value, of which State has none
        postcard::to_stdvec(&state).unwrap_or_default()
    }

    /// The world of `model` (the scene the state was taken of) in the state `bytes` encodes.
    pub fn from_state(model: Model, settings: Settings, bytes: &[u8]) -> Result<World, StateError> {
        let s: State = postcard::from_bytes(bytes).map_err(|e| StateError::Decode(e.to_string()))?;
        let mut world = World::with_settings(model, settings);
        let counts = [
            ("bodies", s.bodies.len(), world.bodies.len()),
            ("connectors", s.connectors.len(), world.connectors.len()),
            ("load points", s.load_points.len(), world.load_points.len()),
            ("monitors", s.monitors.len(), world.monitors.len()),
        ];
        if let Some(&(what, saved, scene)) = counts.iter().find(|(_, a, b)| a != b) {
            return Err(StateError::Mismatch { what, saved, scene });
        }
        let mut bodies = s.bodies;
        for (saved, scene) in bodies.iter_mut().zip(&mut world.bodies) {
            match (&mut saved.mesh, &mut scene.mesh) {
                (Some(a), Some(b)) if a.nodes.len() == b.nodes.len() => {
                    a.pattern = std::mem::take(&mut b.pattern)
                }
                (None, None) => {}
                _ => return Err(StateError::Mismatch { what: "mesh nodes", saved: 0, scene: 0 }),
            }
        }
        world.flex = Flexibility::from_state(s.flex).map_err(|e| StateError::Factor(e.to_string()))?;
        (world.bodies, world.load_points, world.monitors, world.connectors) =
            (bodies, s.load_points, s.monitors, s.connectors);
        (world.step_index, world.time, world.threshold, world.feature) =
            (s.step_index, s.time, s.threshold, s.feature);
        (world.allowance, world.started, world.h) = (s.allowance, s.started, s.h);
        (world.dofs, world.stage, world.memory) = (s.dofs, s.stage, s.memory);
        world.broken = s.broken.into_iter().collect();
        world.pipeline.vi.set_step_length(s.step_length);
        world.stage_settings();
        Ok(world)
    }
}
