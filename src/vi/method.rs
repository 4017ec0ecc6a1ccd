//! The VI methods as values and the chain of them a solve runs (`[solver] method` in the
//! scene; math note §4.17, "The chain of methods").

use std::fmt;

/// One method of a chain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    /// Projection-contraction with the outer compatibility loop (math note §4.2–4.3): the
    /// paper's method, the reference; it takes every problem.
    Pc,
    /// Nonsmooth block Gauss-Seidel with exact local solves (math note §4.7); its stall guard
    /// hands over.
    Nsgs,
    /// The outer compatibility loop of PC with MPRGP (conjugate gradients with proportioning
    /// and projections) as the inner solver of each pass (math note §4.8).
    Mprgp,
    /// Semismooth Newton on the natural map with the friction bounds' dependence on the normal
    /// force in its Jacobian (math note §4.16).
    Newton,
    /// Lemke's complementary pivoting on small Coulomb problems (math note §4.12).
    Lemke,
    /// The linear program of the contact pattern's cell (math note §4.13).
    Cell,
}

impl Method {
    /// Every method with its name in a chain.
    pub const ALL: [(&'static str, Method); 6] = [
        ("pc", Method::Pc),
        ("nsgs", Method::Nsgs),
        ("mprgp", Method::Mprgp),
        ("newton", Method::Newton),
        ("lemke", Method::Lemke),
        ("cell", Method::Cell),
    ];

    /// The method of a name (`pc`, `nsgs`, `mprgp`, `newton`, `lemke`, `cell`).
    pub fn parse(name: &str) -> Option<Method> {
        Self::ALL.iter().find(|(s, _)| *s == name).map(|(_, m)| *m)
    }

    /// Name in a chain and in `steps.csv`.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(_, m)| *m == self).map_or("pc", |(s, _)| s)
    }

    /// Whether the method reads W's entries in CSR form (built from the operator's entries
    /// when it has no CSR storage) and needs blocks of one to three rows.
    pub fn needs_entries(self) -> bool {
        !matches!(self, Method::Pc | Method::Mprgp)
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The most methods a chain lists.
pub const MAX_METHODS: usize = 6;

/// The methods a solve runs, in order, until one answers (math note §4.17): a list of distinct
/// [`Method`]s, the first of them first. [`Chain::named`] gives the chains a single scene name
/// stands for; [`Chain::new`] any other list.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Chain {
    methods: [Method; MAX_METHODS],
    len: usize,
}

impl Default for Chain {
    /// The chain of `method = "auto"`, MPRGP's ([`Chain::NAMES`]).
    fn default() -> Self {
        Chain::named(Method::Mprgp)
    }
}

impl Chain {
    /// The scene names of whole chains (`method = "mprgp"`); `auto` is MPRGP's chain.
    pub const NAMES: [(&'static str, Method); 5] = [
        ("auto", Method::Mprgp),
        ("pc", Method::Pc),
        ("nsgs", Method::Nsgs),
        ("mprgp", Method::Mprgp),
        ("newton", Method::Newton),
    ];

    /// A chain of these methods in this order; `None` when the list is empty, longer than
    /// [`MAX_METHODS`] or names a method twice.
    pub fn new(list: &[Method]) -> Option<Chain> {
        let distinct = list.iter().enumerate().all(|(i, m)| !list[..i].contains(m));
        if list.is_empty() || list.len() > MAX_METHODS || !distinct {
            return None;
        }
        let mut methods = [Method::Pc; MAX_METHODS];
        methods[..list.len()].copy_from_slice(list);
        Some(Chain { methods, len: list.len() })
    }

    /// The chain a method's scene name stands for: the method followed by the methods that
    /// take over when it fails (math note §4.17). PC alone; NSGS, Lemke, the cell program, PC;
    /// MPRGP, then NSGS's chain; Newton, then MPRGP's chain; Lemke or the cell program alone.
    pub fn named(first: Method) -> Chain {
        use Method::*;
        let list: &[Method] = match first {
            Pc => &[Pc],
            Nsgs => &[Nsgs, Lemke, Cell, Pc],
            Mprgp => &[Mprgp, Nsgs, Lemke, Cell, Pc],
            Newton => &[Newton, Mprgp, Nsgs, Lemke, Cell, Pc],
            Lemke => &[Lemke],
            Cell => &[Cell],
        };
        Chain::new(list).unwrap_or(Chain { methods: [Pc; MAX_METHODS], len: 1 })
    }

    /// The chain of a scene name of [`Self::NAMES`].
    pub fn parse(name: &str) -> Option<Chain> {
        Self::NAMES.iter().find(|(s, _)| *s == name).map(|(_, m)| Chain::named(*m))
    }

    /// The names of [`Self::NAMES`], quoted, for messages.
    pub fn names() -> String {
        quoted(Self::NAMES.map(|(s, _)| s))
    }

    /// The chain of a list of method names (`Err(shown)`: an entry that is not a string),
    /// each at most once; else what is wrong with the list.
    pub fn from_list<'a, D: fmt::Display>(
        items: impl Iterator<Item = Result<&'a str, D>>,
    ) -> Result<Chain, String> {
        let mut list = Vec::new();
        for item in items {
            let m = match item {
                Ok(s) => Method::parse(s).ok_or_else(|| format!("\"{s}\"")),
                Err(shown) => Err(shown.to_string()),
            };
            let methods = quoted(Method::ALL.map(|(s, _)| s));
            let m = m.map_err(|shown| format!("lists {shown}, which is not one of {methods}"))?;
            if list.contains(&m) {
                return Err(format!("lists \"{m}\" twice"));
            }
            list.push(m);
        }
        Chain::new(&list).ok_or_else(|| "lists no method".to_string())
    }

    /// The methods in order.
    pub fn methods(&self) -> &[Method] {
        &self.methods[..self.len]
    }

    /// The first method.
    pub fn first(&self) -> Method {
        self.methods[0]
    }

    /// Where `m` stands in the chain (`None` when it is not in it).
    pub fn position(&self, m: Method) -> Option<usize> {
        self.methods().iter().position(|&x| x == m)
    }

    /// The chain without `m` (the chain itself when `m` is its only method).
    pub fn without(&self, m: Method) -> Chain {
        let rest: Vec<Method> = self.methods().iter().copied().filter(|&x| x != m).collect();
        Chain::new(&rest).unwrap_or(*self)
    }

    /// The scene name of a named chain, else the methods joined by commas.
    pub fn name(&self) -> String {
        match Self::NAMES.iter().skip(1).find(|(_, m)| Chain::named(*m) == *self) {
            Some((s, _)) => s.to_string(),
            None => self.methods().iter().map(|m| m.name()).collect::<Vec<_>>().join(","),
        }
    }
}

impl From<Method> for Chain {
    /// [`Chain::named`].
    fn from(m: Method) -> Chain {
        Chain::named(m)
    }
}

/// Names quoted and joined by commas.
fn quoted<const N: usize>(names: [&str; N]) -> String {
    names.map(|s| format!("\"{s}\"")).join(", ")
}
