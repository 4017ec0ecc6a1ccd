//! pbdda: discontinuous deformation analysis of particle-block systems in the
//! variational-inequality form of Fan, Zhao & Zheng (2018), "PB-DDA".
//!
//! One time step, as data flow (see [`world`]; "math note" is `docs/math.md`):
//!
//! ```text
//! scene (TOML)  -> scene::load -> Model            validated input
//! Model         -> World::new                      bodies, flexibilities, contact memory
//! World::step:  predict (body)  -> detect (contact) -> W = B K⁻¹ Bᵀ (cluster)
//!               -> VI solves (vi) -> update (body) -> StepRecord -> output::csv
//! ```
//!
//! Modules from the bottom up (each uses only modules before it; `tests/io/module_graph.rs`
//! checks that there is no import cycle): `geometry`, `sparse` (faer's sparse Cholesky), `error`;
//! `vi` (the variational-inequality solvers, no bodies); `mesh`; `model`; `traction`,
//! `contact`; `body`; `dofs`, `jacobian`, `connector`; `cluster`; `delassus`; `world`;
//! `checkpoint`, `output`, `generate`, `rockmass`, `ntdda`; `scene`; `cli`, `api`.
//!
//! Threads: one pool, micropool's global pool (`micropool::join`: the VI's sweeps, the body
//! form's product, narrow-phase detection, a step's CSV rows, the contact block's forward solves
//! beside its Gram products, math note §9.8). rayon is not used: its `join` from
//! the stepping thread parks the caller, which costs more than a sweep's half on two cores
//! (`src/vi/par.rs`, math note §3.3). Factorizations run sequentially.
//!
//! ```no_run
//! let model = pbdda::scene::load(std::path::Path::new("examples/7_1_disk_heap.toml"))?;
//! let mut world = pbdda::world::World::new(model);
//! let record = world.step()?;
//! println!("{} contacts, residual {:e}", record.contacts.len(), record.residual);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod api;
pub mod body;
pub mod checkpoint;
pub mod cli;
pub mod cluster;
pub mod connector;
pub mod contact;
pub mod delassus;
pub mod dofs;
pub mod error;
pub mod generate;
pub mod geometry;
pub mod jacobian;
pub mod mesh;
pub mod model;
pub mod ntdda;
pub mod output;
pub mod rockmass;
pub mod scene;
pub mod sparse;
pub mod traction;
pub mod vi;
pub mod world;
