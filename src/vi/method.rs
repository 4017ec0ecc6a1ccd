//! The choice of VI method (`[solver] method` in the scene).

/// Which solver [`super::Solver::solve`] runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// The fastest method that meets the tolerance on the whole test suite (measured in
    /// `benches/solvers.rs`): NSGS with its stall guard.
    #[default]
    Auto,
    /// Projection-contraction with the outer compatibility loop (math note §4.2–4.3): the
    /// paper's method, the reference.
    Pc,
    /// Nonsmooth block Gauss-Seidel with exact local solves (math note §4.7); PC when W has
    /// no CSR storage, and PC from the NSGS iterate when the stall guard fires.
    Nsgs,
}

impl Method {
    /// Every method with its scene name.
    pub const ALL: [(&'static str, Method); 3] =
        [("auto", Method::Auto), ("pc", Method::Pc), ("nsgs", Method::Nsgs)];

    /// The method of a scene name (`auto`, `pc`, `nsgs`).
    pub fn parse(name: &str) -> Option<Method> {
        Self::ALL.iter().find(|(s, _)| *s == name).map(|(_, m)| *m)
    }

    /// Scene name.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(_, m)| *m == self).map_or("auto", |(s, _)| s)
    }

    /// The method `Auto` stands for.
    pub fn resolve(self) -> Method {
        match self {
            Method::Auto => Method::Nsgs,
            m => m,
        }
    }
}
