//! The choice of VI method (`[solver] method` in the scene).

/// Rows from which [`Method::Auto`] runs NSGS.
pub const AUTO_NSGS_ROWS: usize = 500;

/// Which solver [`super::Solver::solve`] runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// PC below [`AUTO_NSGS_ROWS`] rows, NSGS with its stall guard from there on: NSGS was the
    /// faster on the measured piles (`benches/solvers.rs`), while on small hyperstatic scenes
    /// the two may pick different (equally valid) force distributions and the suite's tests
    /// of individual forces there were written against PC's (e.g. the §7.2 staircase's
    /// per-contact shears); a small problem costs little with either.
    #[default]
    Auto,
    /// Projection-contraction with the outer compatibility loop (math note §4.2–4.3): the
    /// paper's method, the reference.
    Pc,
    /// Nonsmooth block Gauss-Seidel with exact local solves (math note §4.7); PC when W has
    /// no CSR storage, and PC from the NSGS iterate when the stall guard fires.
    Nsgs,
    /// The outer compatibility loop of PC with MPRGP (conjugate gradients with proportioning
    /// and projections) as the inner solver of each pass (math note §4.8).
    Mprgp,
}

impl Method {
    /// Every method with its scene name.
    pub const ALL: [(&'static str, Method); 4] =
        [("auto", Method::Auto), ("pc", Method::Pc), ("nsgs", Method::Nsgs), ("mprgp", Method::Mprgp)];

    /// The method of a scene name (`auto`, `pc`, `nsgs`).
    pub fn parse(name: &str) -> Option<Method> {
        Self::ALL.iter().find(|(s, _)| *s == name).map(|(_, m)| *m)
    }

    /// Scene name.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(_, m)| *m == self).map_or("auto", |(s, _)| s)
    }

    /// The method `Auto` stands for on a problem of `rows` rows.
    pub fn resolve(self, rows: usize) -> Method {
        match self {
            Method::Auto if rows >= AUTO_NSGS_ROWS => Method::Nsgs,
            Method::Auto => Method::Pc,
            m => m,
        }
    }
}
