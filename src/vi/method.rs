//! The choice of VI method (`[solver] method` in the scene).

/// Which solver [`super::Solver::solve`] runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// MPRGP with its guard: the fastest method that met the tolerance on the whole suite
    /// and on the bench piles (notes of issue 10; `benches/solvers.rs`). On small hyperstatic
    /// scenes it picks the same forces as PC (the §7.2 staircase's per-contact shears), since
    /// each pass solves the same box QP as PC's from the same start.
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
    /// Semismooth Newton on the natural map with the friction bounds' dependence on the normal
    /// force in its Jacobian (math note §4.16); the chain of `Mprgp` from the warm start when
    /// it fails or W has no entries.
    Newton,
}

impl Method {
    /// Every method with its scene name.
    pub const ALL: [(&'static str, Method); 5] = [
        ("auto", Method::Auto),
        ("pc", Method::Pc),
        ("nsgs", Method::Nsgs),
        ("mprgp", Method::Mprgp),
        ("newton", Method::Newton),
    ];

    /// The method of a scene name (`auto`, `pc`, `nsgs`, `mprgp`, `newton`).
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
            Method::Auto => Method::Mprgp,
            m => m,
        }
    }
}
